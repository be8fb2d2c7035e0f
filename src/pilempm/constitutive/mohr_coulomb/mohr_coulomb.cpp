#include "pilempm/constitutive/mohr_coulomb/mohr_coulomb.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>

#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/core/error.hpp"

namespace pilempm {

namespace {

constexpr double kDegree = kPi / 180.0;
// A candidate return is accepted when its multipliers and the yield functions of the returned
// point violate their signs by at most this fraction of the stress scale.
constexpr double kAcceptTolerance = 1.0e-10;

void require(bool condition, const char* key, double value, const std::string& allowed) {
  if (!condition) throw InvalidValue(key, format_value(value), allowed);
}

Vec3 make3(double a, double b, double c) {
  return Vec3(a, b, c);
}

}  // namespace

double MohrCoulombParameters::apex_stress() const {
  if (friction_angle_deg <= 0.0) return std::numeric_limits<double>::infinity();
  return cohesion / std::tan(friction_angle_deg * kDegree);
}

void MohrCoulombParameters::validate() const {
  require(young_modulus > 0.0 && std::isfinite(young_modulus), "young_modulus_Pa", young_modulus,
          "> 0 and finite");
  require(poisson_ratio > -1.0 && poisson_ratio < 0.5, "poisson_ratio", poisson_ratio,
          "in (-1, 0.5)");
  require(cohesion >= 0.0 && std::isfinite(cohesion), "cohesion_Pa", cohesion, ">= 0 and finite");
  require(friction_angle_deg >= 0.0 && friction_angle_deg < 90.0, "friction_angle_deg",
          friction_angle_deg, "in [0, 90) degrees");
  // Without friction and cohesion the material has no shear strength at all (a fluid).
  require(friction_angle_deg > 0.0 || cohesion > 0.0, "cohesion_Pa", cohesion,
          "> 0 when friction_angle_deg = 0 (no shear strength otherwise)");
  require(dilatancy_angle_deg >= 0.0 && dilatancy_angle_deg <= friction_angle_deg,
          "dilatancy_angle_deg", dilatancy_angle_deg,
          fmt::format("in [0, friction_angle_deg = {}] degrees", friction_angle_deg));
  const double apex = apex_stress();
  const bool no_cutoff = std::isinf(tension_cutoff) && tension_cutoff > 0.0;
  require(
      no_cutoff || (tension_cutoff >= 0.0 && tension_cutoff <= apex), "tension_cutoff_Pa",
      tension_cutoff,
      std::isfinite(apex)
          ? fmt::format("in [0, c cot(phi) = {}] (the Mohr-Coulomb apex), or inf for none", apex)
          : std::string(">= 0, or inf for none"));
}

MohrCoulomb::MohrCoulomb(const MohrCoulombParameters& parameters) : parameters_(parameters) {
  parameters_.validate();
  const ElasticParameters elastic{parameters_.young_modulus, parameters_.poisson_ratio};
  stiffness_ = elastic.stiffness();
  bulk_ = elastic.bulk_modulus();
  shear_ = elastic.shear_modulus();

  const double sin_phi = std::sin(parameters_.friction_angle_deg * kDegree);
  const double cos_phi = std::cos(parameters_.friction_angle_deg * kDegree);
  const double sin_psi = std::sin(parameters_.dilatancy_angle_deg * kDegree);
  k_ = (1.0 + sin_phi) / (1.0 - sin_phi);
  const double m = (1.0 + sin_psi) / (1.0 - sin_psi);
  strength_ = 2.0 * parameters_.cohesion * cos_phi / (1.0 - sin_phi);
  apex_ = parameters_.apex_stress();
  tension_cutoff_ = std::min(parameters_.tension_cutoff, apex_);
  cutoff_active_ = tension_cutoff_ < apex_;
  if (!cutoff_active_) tension_cutoff_ = std::numeric_limits<double>::infinity();

  const double lame = bulk_ - 2.0 / 3.0 * shear_;
  const Mat3 principal_stiffness = lame * Mat3::Ones() + 2.0 * shear_ * Mat3::Identity();
  const Vec3 normals[kPlanes] = {make3(k_, 0, -1), make3(0, k_, -1), make3(k_, -1, 0),
                                 make3(1, 0, 0),   make3(0, 1, 0),   make3(0, 0, 1)};
  const Vec3 flows[kPlanes] = {make3(m, 0, -1), make3(0, m, -1), make3(m, -1, 0),
                               make3(1, 0, 0),  make3(0, 1, 0),  make3(0, 0, 1)};
  for (int i = 0; i < kPlanes; ++i) {
    planes_[i].normal = normals[i];
    planes_[i].flow = flows[i];
    planes_[i].stiffness_flow = principal_stiffness * flows[i];
    planes_[i].level = i < 3 ? strength_ : tension_cutoff_;
  }
}

double MohrCoulomb::yield_value(int plane, const Vec3& s) const {
  return planes_[plane].normal.dot(s) - planes_[plane].level;
}

double MohrCoulomb::violation(const Vec3& returned, unsigned active, double scale) const {
  const int count = cutoff_active_ ? kPlanes : 3;
  double worst = 0.0;
  for (int i = 0; i < count; ++i)
    if (!(active & (1u << i))) worst = std::max(worst, yield_value(i, returned) / scale);
  return worst;
}

double MohrCoulomb::cone_violation(const Vec3& difference, const int* planes, int count,
                                   double scale) const {
  // Is difference = sum_j dlambda_j D b_j with dlambda_j >= 0? With four generators in 3D it is iff
  // one of the triples represents it with non-negative weights (Caratheodory).
  double best = std::numeric_limits<double>::infinity();
  for (int skip = (count == 4 ? 0 : -1); skip < (count == 4 ? 4 : 0); ++skip) {
    Mat3 generators;
    int column = 0;
    for (int j = 0; j < count; ++j)
      if (j != skip) generators.col(column++) = planes_[planes[j]].stiffness_flow;
    const double det = generators.determinant();
    if (!(std::abs(det) > 1.0e-12 * generators.colwise().norm().prod())) continue;
    const Vec3 weights = generators.partialPivLu().solve(difference);
    double worst = 0.0;
    for (int j = 0; j < 3; ++j)
      worst = std::max(worst, -weights[j] * generators.col(j).norm() / scale);
    best = std::min(best, worst);
  }
  return best;
}

MohrCoulomb::PrincipalReturn MohrCoulomb::return_principal(const Vec3& s) const {
  PrincipalReturn out;
  out.stress = s;
  const double f_trial = yield_value(0, s);
  const double ft_trial = cutoff_active_ ? yield_value(3, s) : -1.0;
  if (f_trial <= 0.0 && ft_trial <= 0.0) return out;

  double scale = std::max({s.cwiseAbs().maxCoeff(), strength_, parameters_.cohesion,
                           std::numeric_limits<double>::min()});
  if (cutoff_active_) scale = std::max(scale, tension_cutoff_);

  double best_violation = std::numeric_limits<double>::infinity();
  auto consider = [&](const Vec3& returned, ReturnRegion region, unsigned active,
                      double candidate_violation) {
    if (!(candidate_violation < best_violation)) return false;
    best_violation = candidate_violation;
    out.stress = returned;
    out.region = region;
    out.active = active;
    return candidate_violation <= kAcceptTolerance;
  };

  // Return to one plane i: s - dl D b_i with f_i = 0, dl = f_i(s) / (a_i . D b_i).
  auto plane_return = [&](int i, ReturnRegion region) {
    const Plane& p = planes_[i];
    const double multiplier = yield_value(i, s) / p.normal.dot(p.stiffness_flow);
    const Vec3 returned = s - multiplier * p.stiffness_flow;
    const double bad = std::max(violation(returned, 1u << i, scale),
                                -multiplier * p.stiffness_flow.norm() / scale);
    return consider(returned, region, 1u << i, bad);
  };
  // Return to the line where planes i and j meet: s - dl_i D b_i - dl_j D b_j with f_i = f_j = 0.
  auto line_return = [&](int i, int j, ReturnRegion region) {
    const Plane& p = planes_[i];
    const Plane& q = planes_[j];
    Eigen::Matrix2d a;
    a << p.normal.dot(p.stiffness_flow), p.normal.dot(q.stiffness_flow),
        q.normal.dot(p.stiffness_flow), q.normal.dot(q.stiffness_flow);
    if (!(std::abs(a.determinant()) > 1.0e-12 * a.squaredNorm())) return false;
    const Eigen::Vector2d multiplier =
        a.inverse() * Eigen::Vector2d(yield_value(i, s), yield_value(j, s));
    const Vec3 returned = s - multiplier[0] * p.stiffness_flow - multiplier[1] * q.stiffness_flow;
    double bad = violation(returned, (1u << i) | (1u << j), scale);
    bad = std::max(bad, -multiplier[0] * p.stiffness_flow.norm() / scale);
    bad = std::max(bad, -multiplier[1] * q.stiffness_flow.norm() / scale);
    return consider(returned, region, (1u << i) | (1u << j), bad);
  };
  // Return to a corner point where the listed planes meet.
  auto point_return = [&](const Vec3& corner, std::initializer_list<int> active,
                          ReturnRegion region) {
    unsigned mask = 0;
    for (int i : active) mask |= 1u << i;
    const double bad = std::max(
        violation(corner, mask, scale),
        cone_violation(s - corner, active.begin(), static_cast<int>(active.size()), scale));
    return consider(corner, region, mask, bad);
  };

  using R = ReturnRegion;
  if (plane_return(0, R::plane)) return out;
  if (cutoff_active_ && plane_return(3, R::tension_plane)) return out;
  if (line_return(0, 1, R::compression_edge)) return out;
  if (line_return(0, 2, R::extension_edge)) return out;
  if (cutoff_active_) {
    const double t = tension_cutoff_;
    const double low = k_ * t - strength_;  // s3 on the Mohr-Coulomb plane when s1 = t
    if (line_return(0, 3, R::plane_tension_line)) return out;
    if (line_return(3, 4, R::tension_edge)) return out;
    if (point_return(make3(t, low, low), {0, 2, 3}, R::extension_tension_corner)) return out;
    if (point_return(make3(t, t, low), {0, 1, 3, 4}, R::compression_tension_corner)) return out;
    if (point_return(make3(t, t, t), {3, 4, 5}, R::tension_apex)) return out;
  } else if (std::isfinite(apex_)) {
    // Every trial stress that no other return accepts belongs to the apex (see the header).
    out.stress = Vec3::Constant(apex_);
    out.region = R::apex;
    out.active = 0b111u;
    return out;
  }
  out.consistent = false;  // keep the candidate with the smallest violation
  return out;
}

UpdateResult MohrCoulomb::update(MaterialState& state, const Vec6& strain_increment) const {
  UpdateResult result;
  if (!state.stress.allFinite() || !strain_increment.allFinite() ||
      !std::isfinite(state.void_ratio)) {
    result.ok = false;
    result.message = "mohr-coulomb: non-finite stress, void ratio or strain increment";
    return result;
  }
  const Vec6 trial = state.stress + stiffness_ * strain_increment;
  Vec6 stress = trial;
  double plastic_shear = 0.0;

  Eigen::SelfAdjointEigenSolver<Mat3> spectral(to_matrix(trial));
  if (spectral.info() != Eigen::Success) {
    result.ok = false;
    result.message = "mohr-coulomb: spectral decomposition of the trial stress failed";
    return result;
  }
  const Vec3 ascending = spectral.eigenvalues();
  const Vec3 sorted(ascending[2], ascending[1], ascending[0]);
  const PrincipalReturn returned = return_principal(sorted);
  if (returned.region != ReturnRegion::elastic) {
    const Mat3& vectors = spectral.eigenvectors();  // columns in ascending order
    const Vec3 new_ascending(returned.stress[2], returned.stress[1], returned.stress[0]);
    stress = from_matrix(vectors * new_ascending.asDiagonal() * vectors.transpose());
    // dev(d eps_p) = dev(trial - new) / 2G, coaxial with the trial stress.
    const Vec3 relaxed = sorted - returned.stress;
    const Vec3 relaxed_dev = relaxed - Vec3::Constant(relaxed.sum() / 3.0);
    plastic_shear = std::sqrt(2.0 / 3.0) * relaxed_dev.norm() / (2.0 * shear_);
    // At an apex the returned stress is fixed: it no longer changes with the strain.
    result.at_apex =
        returned.region == ReturnRegion::apex || returned.region == ReturnRegion::tension_apex;
  }
  const double void_ratio = state.void_ratio + (1.0 + state.void_ratio) * trace(strain_increment);
  if (!stress.allFinite() || !std::isfinite(void_ratio)) {
    result.ok = false;
    result.message = "mohr-coulomb: the update produced a non-finite stress or void ratio";
    return result;
  }
  state.stress = stress;
  state.void_ratio = void_ratio;
  plastic_shear_strain(state) += plastic_shear;
  result.substeps = 1;
  return result;
}

bool MohrCoulomb::consistent_tangent(const MaterialState& state, const Vec6& strain_increment,
                                     Mat6& tangent) const {
  const Vec6 trial = state.stress + stiffness_ * strain_increment;
  Eigen::SelfAdjointEigenSolver<Mat3> spectral(to_matrix(trial));
  if (spectral.info() != Eigen::Success) return false;
  const Vec3 ascending = spectral.eigenvalues();
  const Vec3 sorted(ascending[2], ascending[1], ascending[0]);
  const PrincipalReturn returned = return_principal(sorted);
  if (!returned.consistent) return false;
  if (returned.region == ReturnRegion::elastic) {
    tangent = stiffness_;
    return true;
  }
  // The return's derivative in principal space, dσ_i/dσ^tr_j.
  Mat3 principal = Mat3::Zero();
  int count = 0;
  int planes[kPlanes];
  for (int i = 0; i < kPlanes; ++i)
    if (returned.active & (1u << i)) planes[count++] = i;
  if (count <= 2) {
    Eigen::Matrix<double, 3, Eigen::Dynamic> normals(3, count), stiffness_flows(3, count);
    for (int k = 0; k < count; ++k) {
      normals.col(k) = planes_[planes[k]].normal;
      stiffness_flows.col(k) = planes_[planes[k]].stiffness_flow;
    }
    const Eigen::MatrixXd coupling = normals.transpose() * stiffness_flows;  // Aᵀ D B
    principal =
        Mat3::Identity() - stiffness_flows * coupling.partialPivLu().solve(normals.transpose());
  }  // a corner or the apex: the returned stress does not move
  // The eigenvectors in the order of `sorted` (the solver's columns ascend).
  Mat3 n;
  for (int i = 0; i < 3; ++i) n.col(i) = spectral.eigenvectors().col(2 - i);
  const double scale = std::max(sorted.cwiseAbs().maxCoeff(), strength_) + 1.0;
  // The spin terms' factors (σ_i − σ_j) / (σ^tr_i − σ^tr_j), their limit where the trial
  // eigenvalues meet.
  double spin[3][3] = {};
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j) {
      const double gap = sorted[i] - sorted[j];
      spin[i][j] =
          std::abs(gap) > 1.0e-10 * scale
              ? (returned.stress[i] - returned.stress[j]) / gap
              : 0.5 * (principal(i, i) - principal(i, j) - principal(j, i) + principal(j, j));
    }
  // dσ/dσ^tr column by column on the Mandel basis E, then times the elastic stiffness.
  Mat6 derivative;
  for (int c = 0; c < 6; ++c) {
    const Mat3 e = to_matrix(Vec6::Unit(c));
    Vec3 normal_part;
    for (int j = 0; j < 3; ++j) normal_part[j] = n.col(j).dot(e * n.col(j));
    const Vec3 principal_change = principal * normal_part;
    Mat3 change = Mat3::Zero();
    for (int i = 0; i < 3; ++i) {
      change += principal_change[i] * n.col(i) * n.col(i).transpose();
      for (int j = i + 1; j < 3; ++j)
        change += spin[i][j] * n.col(i).dot(e * n.col(j)) *
                  (n.col(i) * n.col(j).transpose() + n.col(j) * n.col(i).transpose());
    }
    derivative.col(c) = from_matrix(change);
  }
  tangent = derivative * stiffness_;
  return true;
}

Mat6 MohrCoulomb::tangent(const MaterialState&, const Vec6&) const {
  return stiffness_;
}

double MohrCoulomb::wave_modulus(const MaterialState&) const {
  return bulk_ + 4.0 / 3.0 * shear_;
}

double MohrCoulomb::mohr_coulomb_function(const Vec6& stress) const {
  const Vec3 ascending = principal_values(stress);
  const double phi = parameters_.friction_angle_deg * kDegree;
  return (ascending[2] - ascending[0]) + (ascending[2] + ascending[0]) * std::sin(phi) -
         2.0 * parameters_.cohesion * std::cos(phi);
}

double MohrCoulomb::tension_function(const Vec6& stress) const {
  if (!cutoff_active_) return -std::numeric_limits<double>::infinity();
  return principal_values(stress)[2] - tension_cutoff_;
}

namespace {
constexpr HistoryVariable kHistory[] = {{"plastic_shear_strain", 0, 1, false}};
}  // namespace

std::span<const HistoryVariable> MohrCoulomb::history_variables() const {
  return kHistory;
}

}  // namespace pilempm
