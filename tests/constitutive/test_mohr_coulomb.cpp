// Mohr-Coulomb with non-associated flow and tension cut-off: exact return mapping checked against
// its defining conditions (on the surface, plastic strain in the cone of the potential gradients),
// validation, isotropy. Its drained triaxial limits and dilatancy, through the element driver, are
// in tests/element/test_mohr_coulomb_triaxial.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "../support/material_builders.hpp"
#include "pilempm/constitutive/mohr_coulomb/mohr_coulomb.hpp"
#include "pilempm/core/error.hpp"

namespace pilempm {
namespace {

using Region = MohrCoulomb::ReturnRegion;

constexpr double kE = 50.0e6;
constexpr double kNu = 0.3;
constexpr double kInf = std::numeric_limits<double>::infinity();

double deg(double d) {
  return d * kPi / 180.0;
}

MohrCoulombParameters make(double c, double phi, double psi, double t = kInf) {
  return test_support::mohr_coulomb_parameters(kE, kNu, c, phi, psi, t);
}

// Hooke's law in Mandel notation, built independently of the library.
Mat6 hooke(double e, double nu) {
  const double lame = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  const double g = e / (2.0 * (1.0 + nu));
  Mat6 d = Mat6::Zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) d(i, j) = lame + (i == j ? 2.0 * g : 0.0);
  for (int i = 3; i < 6; ++i) d(i, i) = 2.0 * g;
  return d;
}

Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q.toRotationMatrix();
}

// Principal values, descending, and the matching eigenvectors as columns.
struct Spectral {
  Vec3 values;
  Mat3 vectors;
};
Spectral spectral(const Vec6& a) {
  Eigen::SelfAdjointEigenSolver<Mat3> s(to_matrix(a));
  Spectral out;
  out.values = s.eigenvalues().reverse();
  out.vectors = s.eigenvectors().rowwise().reverse();
  return out;
}

// Standard form (s1 - s3) + (s1 + s3) sin phi - 2 c cos phi, tension positive, s1 >= s3.
double mc_function(const Vec3& sorted, double c, double phi_deg) {
  return (sorted[0] - sorted[2]) + (sorted[0] + sorted[2]) * std::sin(deg(phi_deg)) -
         2.0 * c * std::cos(deg(phi_deg));
}

// Is x a non-negative combination of the generators (up to tol relative to |x|)?
bool in_cone(const std::vector<Vec3>& generators, const Vec3& x, double tol) {
  const double size = x.norm();
  if (size == 0.0) return true;
  const int n = static_cast<int>(generators.size());
  auto try_subset = [&](const std::vector<int>& subset) {
    Eigen::MatrixXd g(3, static_cast<Eigen::Index>(subset.size()));
    for (std::size_t j = 0; j < subset.size(); ++j)
      g.col(static_cast<Eigen::Index>(j)) = generators[subset[j]];
    const Eigen::VectorXd w = g.colPivHouseholderQr().solve(x);
    if ((g * w - x).norm() > tol * size) return false;
    for (std::size_t j = 0; j < subset.size(); ++j)
      if (w[static_cast<Eigen::Index>(j)] * generators[subset[j]].norm() < -tol * size)
        return false;
    return true;
  };
  for (int i = 0; i < n; ++i) {
    if (try_subset({i})) return true;
    for (int j = i + 1; j < n; ++j) {
      if (try_subset({i, j})) return true;
      for (int k = j + 1; k < n; ++k)
        if (try_subset({i, j, k})) return true;
    }
  }
  return false;
}

// Potential gradients in sorted principal space: Mohr-Coulomb pair (i major, j minor), Rankine i.
Vec3 mc_flow(int i, int j, double psi_deg) {
  const double m = (1.0 + std::sin(deg(psi_deg))) / (1.0 - std::sin(deg(psi_deg)));
  Vec3 b = Vec3::Zero();
  b[i] = m;
  b[j] = -1.0;
  return b;
}
Vec3 tension_flow(int i) {
  return Vec3::Unit(i);
}

bool is_mc_region(Region r) {
  return r == Region::plane || r == Region::compression_edge || r == Region::extension_edge ||
         r == Region::apex || r == Region::plane_tension_line ||
         r == Region::compression_tension_corner || r == Region::extension_tension_corner;
}
bool is_tension_region(Region r) {
  return r == Region::tension_plane || r == Region::tension_edge || r == Region::tension_apex ||
         r == Region::plane_tension_line || r == Region::compression_tension_corner ||
         r == Region::extension_tension_corner;
}

// The potential gradients of the surfaces active in each region (independent of the library).
std::vector<Vec3> active_flows(Region r, double psi) {
  switch (r) {
    case Region::plane:
      return {mc_flow(0, 2, psi)};
    case Region::compression_edge:
      return {mc_flow(0, 2, psi), mc_flow(1, 2, psi)};
    case Region::extension_edge:
      return {mc_flow(0, 2, psi), mc_flow(0, 1, psi)};
    case Region::apex:  // all six planes meet at the apex
      return {mc_flow(0, 2, psi), mc_flow(1, 2, psi), mc_flow(0, 1, psi),
              mc_flow(2, 0, psi), mc_flow(2, 1, psi), mc_flow(1, 0, psi)};
    case Region::tension_plane:
      return {tension_flow(0)};
    case Region::tension_edge:
      return {tension_flow(0), tension_flow(1)};
    case Region::tension_apex:
      return {tension_flow(0), tension_flow(1), tension_flow(2)};
    case Region::plane_tension_line:
      return {mc_flow(0, 2, psi), tension_flow(0)};
    case Region::compression_tension_corner:
      return {mc_flow(0, 2, psi), mc_flow(1, 2, psi), tension_flow(0), tension_flow(1)};
    case Region::extension_tension_corner:
      return {mc_flow(0, 2, psi), mc_flow(0, 1, psi), tension_flow(0)};
    case Region::elastic:
      break;
  }
  return {};
}

struct Config {
  const char* label;
  MohrCoulombParameters parameters;
  double low, high;  // sampling box of the principal trial stresses [Pa]
  std::vector<Region> expected;
};

std::vector<Config> configs() {
  const std::vector<Region> mc = {Region::elastic, Region::plane, Region::compression_edge,
                                  Region::extension_edge, Region::apex};
  const std::vector<Region> all = {Region::elastic,
                                   Region::plane,
                                   Region::compression_edge,
                                   Region::extension_edge,
                                   Region::tension_plane,
                                   Region::tension_edge,
                                   Region::tension_apex,
                                   Region::plane_tension_line,
                                   Region::compression_tension_corner,
                                   Region::extension_tension_corner};
  const std::vector<Region> tresca = {Region::elastic, Region::plane, Region::compression_edge,
                                      Region::extension_edge};
  return {
      {"c20k-phi30-psi10", make(20e3, 30, 10), -300e3, 80e3, mc},
      {"c20k-phi30-psi30", make(20e3, 30, 30), -300e3, 80e3, mc},
      {"c0-phi35-psi0", make(0, 35, 0), -300e3, 50e3, mc},
      {"c20k-phi25-psi0", make(20e3, 25, 0), -300e3, 100e3, mc},
      {"c20k-phi30-psi10-t10k", make(20e3, 30, 10, 10e3), -250e3, 60e3, all},
      {"c20k-phi40-psi40-t0", make(20e3, 40, 40, 0.0), -100e3, 60e3, all},
      {"c50k-phi0-tresca", make(50e3, 0, 0), -300e3, 300e3, tresca},
      {"c50k-phi0-t20k", make(50e3, 0, 0, 20e3), -300e3, 100e3, all},
  };
}

// (b) For random trial stresses in every region: the returned stress is admissible and on the
// active surfaces, the plastic strain D^-1 (trial - returned) is coaxial with the trial stress and
// lies in the cone of the active potential gradients, and the plastic shear strain grows by
// sqrt(2/3) |dev d eps_p|.
TEST(MohrCoulomb, ReturnIsOnTheSurfaceWithPlasticStrainAlongThePotential) {
  const Mat6 compliance = hooke(kE, kNu).inverse();
  for (const Config& config : configs()) {
    SCOPED_TRACE(config.label);
    const MohrCoulombParameters& p = config.parameters;
    const MohrCoulomb model(p);
    const double t = model.effective_tension_cutoff();
    std::mt19937 rng(12345);
    std::uniform_real_distribution<double> u(config.low, config.high);
    std::map<Region, int> hits;
    for (int sample = 0; sample < 20000; ++sample) {
      const Vec3 principal(u(rng), u(rng), u(rng));
      const Vec6 trial =
          rotate(diagonal6(principal[0], principal[1], principal[2]), random_rotation(rng));
      MaterialState state;
      state.stress = trial;
      state.void_ratio = 0.7;
      const UpdateResult result = model.update(state, Vec6::Zero());
      ASSERT_TRUE(result.ok);
      EXPECT_EQ(state.void_ratio, 0.7);

      const Spectral before = spectral(trial);
      const MohrCoulomb::PrincipalReturn ret = model.return_principal(before.values);
      ASSERT_TRUE(ret.consistent);
      ++hits[ret.region];

      const double scale = std::max(trial.cwiseAbs().maxCoeff(), 2.0 * p.cohesion);
      const Vec3 after = spectral(state.stress).values;
      // Admissible.
      EXPECT_LE(mc_function(after, p.cohesion, p.friction_angle_deg), 1e-9 * scale);
      if (std::isfinite(t)) {
        EXPECT_LE(after[0] - t, 1e-9 * scale);
      }
      if (ret.region == Region::elastic) {
        EXPECT_EQ(state.stress, trial);
        EXPECT_EQ(MohrCoulomb::plastic_shear_strain(state), 0.0);
        continue;
      }
      // On the active surfaces.
      if (is_mc_region(ret.region)) {
        EXPECT_NEAR(mc_function(after, p.cohesion, p.friction_angle_deg), 0.0, 1e-9 * scale);
      }
      if (is_tension_region(ret.region)) {
        EXPECT_NEAR(after[0], t, 1e-9 * scale);
      }
      if (ret.region == Region::apex) {
        EXPECT_NEAR((after - Vec3::Constant(p.apex_stress())).norm(), 0.0, 1e-9 * scale);
      }

      // The plastic strain in the trial's principal axes: diagonal, and in the cone.
      const Vec6 plastic = compliance * (trial - state.stress);
      const Mat3 in_axes = before.vectors.transpose() * to_matrix(plastic) * before.vectors;
      const double size = plastic.norm();
      EXPECT_LE((in_axes - Mat3(in_axes.diagonal().asDiagonal())).norm(), 1e-8 * size);
      // At the apex with psi = 0 the potential has no volumetric part, so no return along it
      // reaches the apex: the apex takes exactly the trial stresses with a mean stress beyond it.
      if (ret.region == Region::apex && p.dilatancy_angle_deg == 0.0) {
        EXPECT_GE(trace(trial) / 3.0, p.apex_stress() - 1e-9 * scale);
      } else {
        EXPECT_TRUE(
            in_cone(active_flows(ret.region, p.dilatancy_angle_deg), in_axes.diagonal(), 1e-8))
            << "region " << static_cast<int>(ret.region) << " trial " << before.values.transpose()
            << " returned " << after.transpose();
      }
      const double expected_shear = std::sqrt(2.0 / 3.0) * deviator(plastic).norm();
      EXPECT_NEAR(MohrCoulomb::plastic_shear_strain(state), expected_shear,
                  1e-9 * expected_shear + 1e-18);
    }
    for (Region r : config.expected) EXPECT_GE(hits[r], 5) << "region " << static_cast<int>(r);
  }
}

// The return map is continuous: walking along straight lines through all regions in small steps,
// the returned (sorted) stress never jumps. A gap or an overlap between the regions would.
TEST(MohrCoulomb, ReturnMapIsContinuousAcrossRegionBoundaries) {
  for (const Config& config : configs()) {
    SCOPED_TRACE(config.label);
    const MohrCoulomb model(config.parameters);
    std::mt19937 rng(99);
    std::uniform_real_distribution<double> u(config.low, config.high);
    const double step_size = 1e-3 * (config.high - config.low);
    auto returned = [&](const Vec3& s) {
      Vec3 sorted = s;
      std::sort(sorted.data(), sorted.data() + 3, std::greater<double>());
      return model.return_principal(sorted).stress;
    };
    for (int line = 0; line < 200; ++line) {
      const Vec3 a(u(rng), u(rng), u(rng));
      const Vec3 b(u(rng), u(rng), u(rng));
      const int steps = static_cast<int>((b - a).norm() / step_size) + 1;
      Vec3 previous = returned(a);
      for (int i = 1; i <= steps; ++i) {
        const Vec3 s = a + (b - a) * (static_cast<double>(i) / steps);
        const Vec3 current = returned(s);
        ASSERT_LE((current - previous).norm(), 5.0 * (b - a).norm() / steps)
            << "jump near " << s.transpose();
        previous = current;
      }
    }
  }
}

// The consistent tangent (MohrCoulomb::consistent_tangent) is the derivative of update()'s stress
// with respect to the strain increment: against central differences of update() from a
// stress-free start over random increments whose trial stresses reach every return region, in
// rotated axes (so the spin of the eigenvectors counts). Samples whose perturbed trials fall in
// another region (a kink of the map) are skipped.
TEST(MohrCoulomb, ConsistentTangentIsTheDerivativeOfTheUpdate) {
  const Mat6 compliance = hooke(kE, kNu).inverse();
  for (const Config& config : configs()) {
    SCOPED_TRACE(config.label);
    const MohrCoulomb model(config.parameters);
    std::mt19937 rng(2024);
    std::uniform_real_distribution<double> u(config.low, config.high);
    std::map<Region, int> checked;
    double worst = 0.0;
    for (int sample = 0; sample < 3000; ++sample) {
      const Vec3 principal(u(rng), u(rng), u(rng));
      const Vec6 trial =
          rotate(diagonal6(principal[0], principal[1], principal[2]), random_rotation(rng));
      MaterialState start;
      start.void_ratio = 0.7;
      const Vec6 increment = compliance * trial;
      Mat6 analytic;
      ASSERT_TRUE(model.consistent_tangent(start, increment, analytic));
      const Region region = model.return_principal(spectral(trial).values).region;
      const double h = 1e-7 * increment.norm();
      Mat6 numeric;
      bool smooth = true;
      for (int c = 0; c < 6 && smooth; ++c) {
        MaterialState plus = start, minus = start;
        const Vec6 e = h * Vec6::Unit(c);
        model.update(plus, increment + e);
        model.update(minus, increment - e);
        for (const Vec6& side : {Vec6(increment + e), Vec6(increment - e)})
          if (model.return_principal(spectral(hooke(kE, kNu) * side).values).region != region)
            smooth = false;
        numeric.col(c) = (plus.stress - minus.stress) / (2.0 * h);
      }
      if (!smooth) continue;
      ++checked[region];
      const double error = (analytic - numeric).norm() / hooke(kE, kNu).norm();
      worst = std::max(worst, error);
      EXPECT_LT(error, 1e-5) << "region " << static_cast<int>(region) << " trial "
                             << spectral(trial).values.transpose();
    }
    std::printf("%s: largest relative error %.2e over", config.label, worst);
    for (const auto& [region, count] : checked) std::printf(" %d:%d", int(region), count);
    std::printf("\n");
    for (Region r : config.expected) EXPECT_GE(checked[r], 2) << "region " << static_cast<int>(r);
  }
}

// (a) Below yield the update is Hooke's law exactly, and the void ratio follows (1 + e) tr(d eps).
TEST(MohrCoulomb, ElasticBelowYieldEqualsHooke) {
  const MohrCoulomb model(make(10e3, 30, 5, 5e3));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 100; ++i) {
    MaterialState state;
    state.stress = diagonal6(-100e3, -100e3, -100e3);
    state.void_ratio = 0.65;
    Vec6 d_eps;
    for (int j = 0; j < 6; ++j) d_eps[j] = 1e-5 * u(rng);
    const Vec6 expected = state.stress + hooke(kE, kNu) * d_eps;
    ASSERT_LT(model.mohr_coulomb_function(expected), 0.0);
    const UpdateResult result = model.update(state, d_eps);
    ASSERT_TRUE(result.ok);
    EXPECT_LE((state.stress - expected).norm(), 1e-9 * expected.norm());
    EXPECT_NEAR(state.void_ratio, 0.65 + 1.65 * trace(d_eps), 1e-15);
    EXPECT_EQ(MohrCoulomb::plastic_shear_strain(state), 0.0);
  }
}

// UpdateResult::at_apex says when the stress was returned to an apex (where it no longer
// changes with the strain): Mohr-Coulomb's without a cut-off, the cut-off's with one; not for
// an elastic step or a return to a plane.
TEST(MohrCoulomb, AnUpdateSaysWhenItReturnedToAnApex) {
  const auto update = [](const MohrCoulomb& model, double mean_strain, double shear_strain,
                         Vec6& stress) {
    MaterialState state;
    state.stress = diagonal6(-20e3, -20e3, -20e3);
    state.void_ratio = 0.65;
    const Vec6 strain =
        diagonal6(mean_strain + shear_strain, mean_strain - shear_strain, mean_strain);
    const UpdateResult result = model.update(state, strain);
    EXPECT_TRUE(result.ok);
    stress = state.stress;
    return result.at_apex;
  };
  Vec6 stress;
  const MohrCoulomb no_cutoff(make(1e3, 33, 5));
  // Pulled apart by 1e-3 in every direction (about 50 kPa of tension at E = 50 MPa).
  EXPECT_TRUE(update(no_cutoff, 1e-3, 0.0, stress));
  EXPECT_NEAR((stress - Vec6(diagonal6(1.0, 1.0, 1.0) * make(1e3, 33, 5).apex_stress())).norm(),
              0.0, 1e-6);
  EXPECT_FALSE(update(no_cutoff, -1e-5, 0.0, stress));   // compressed a little: elastic
  EXPECT_FALSE(update(no_cutoff, -2e-3, 6e-3, stress));  // sheared under compression: a plane
  EXPECT_LT(std::abs(no_cutoff.mohr_coulomb_function(stress)), 1e-6 * stress.norm());
  const MohrCoulomb with_cutoff(make(10e3, 30, 5, 2e3));
  EXPECT_TRUE(update(with_cutoff, 1e-3, 0.0, stress));
  EXPECT_NEAR((stress - diagonal6(2e3, 2e3, 2e3)).norm(), 0.0, 1e-6);
}

TEST(MohrCoulomb, TangentIsElasticAndWaveModulusIsConstrainedModulus) {
  const MohrCoulomb model(make(10e3, 30, 5));
  MaterialState state;
  state.stress = diagonal6(-1e5, -2e5, -3e5);
  EXPECT_LE((model.tangent(state, Vec6::Ones()) - hooke(kE, kNu)).norm(), 1e-6);
  const double constrained = kE * (1.0 - kNu) / ((1.0 + kNu) * (1.0 - 2.0 * kNu));
  EXPECT_NEAR(model.wave_modulus(state), constrained, 1e-9 * constrained);
  EXPECT_EQ(model.name(), "mohr-coulomb");
}

TEST(MohrCoulomb, NonFiniteInputFailsAndLeavesTheStateUnchanged) {
  const MohrCoulomb model(make(10e3, 30, 5));
  MaterialState state;
  state.stress = diagonal6(-1e5, -1e5, -1e5);
  state.void_ratio = 0.7;
  const MaterialState before = state;
  Vec6 d_eps = Vec6::Zero();
  d_eps[2] = std::numeric_limits<double>::quiet_NaN();
  UpdateResult result = model.update(state, d_eps);
  EXPECT_FALSE(result.ok);
  EXPECT_NE(std::string(result.message), "");
  EXPECT_EQ(state.stress, before.stress);
  EXPECT_EQ(state.void_ratio, before.void_ratio);
  state.stress[4] = kInf;
  result = model.update(state, Vec6::Zero());
  EXPECT_FALSE(result.ok);
  state = before;
  state.void_ratio = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(model.update(state, Vec6::Zero()).ok);
}

// (f) Every impossible value is rejected with an InvalidValue that names its key.
TEST(MohrCoulomb, ValidationNamesTheKey) {
  struct Bad {
    std::function<void(MohrCoulombParameters&)> change;
    const char* key;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Bad> bad = {
      {[](auto& p) { p.young_modulus = 0.0; }, "young_modulus"},
      {[](auto& p) { p.young_modulus = -1e6; }, "young_modulus"},
      {[&](auto& p) { p.young_modulus = nan; }, "young_modulus"},
      {[](auto& p) { p.young_modulus = kInf; }, "young_modulus"},
      {[](auto& p) { p.poisson_ratio = 0.5; }, "poisson_ratio"},
      {[](auto& p) { p.poisson_ratio = -1.0; }, "poisson_ratio"},
      {[](auto& p) { p.cohesion = -1.0; }, "cohesion"},
      {[&](auto& p) { p.cohesion = nan; }, "cohesion"},
      {[](auto& p) { p.friction_angle_deg = -1.0; }, "friction_angle_deg"},
      {[](auto& p) { p.friction_angle_deg = 90.0; }, "friction_angle_deg"},
      {[&](auto& p) { p.friction_angle_deg = nan; }, "friction_angle_deg"},
      {[](auto& p) { p.dilatancy_angle_deg = -1.0; }, "dilatancy_angle_deg"},
      {[](auto& p) { p.dilatancy_angle_deg = 31.0; }, "dilatancy_angle_deg"},
      {[](auto& p) { p.tension_cutoff = -1.0; }, "tension_cutoff"},
      {[](auto& p) { p.tension_cutoff = 10e3 / std::tan(deg(30.0)) * 1.001; }, "tension_cutoff"},
      {[&](auto& p) { p.tension_cutoff = nan; }, "tension_cutoff"},
      {[](auto& p) { p.tension_cutoff = -kInf; }, "tension_cutoff"},
      {[](auto& p) {
         p.cohesion = 0.0;
         p.friction_angle_deg = 0.0;
         p.dilatancy_angle_deg = 0.0;
       },
       "cohesion"},
  };
  for (const Bad& b : bad) {
    MohrCoulombParameters p = make(10e3, 30, 10);
    b.change(p);
    try {
      p.validate();
      ADD_FAILURE() << "accepted a bad " << b.key;
    } catch (const InvalidValue& e) {
      EXPECT_NE(std::string(e.what()).find(b.key), std::string::npos) << e.what();
      EXPECT_NE(e.key().find(b.key), std::string::npos);
    }
    EXPECT_THROW(MohrCoulomb{p}, InvalidValue) << b.key;
  }
  // Edge values that are allowed.
  for (double t : {0.0, 10e3 / std::tan(deg(30.0)), kInf})
    EXPECT_NO_THROW(make(10e3, 30, 30, t).validate()) << t;
  EXPECT_NO_THROW(make(10e3, 0, 0, 1e9).validate());  // Tresca: no apex, any finite cut-off
  EXPECT_NO_THROW(make(0, 30, 0, 0.0).validate());
  EXPECT_FALSE(MohrCoulomb(make(10e3, 30, 10, 10e3 / std::tan(deg(30.0)))).has_tension_cutoff());
  EXPECT_TRUE(MohrCoulomb(make(10e3, 30, 10, 1e3)).has_tension_cutoff());
}

// (g) Isotropy/objectivity: a rotated strain increment from a rotated stress gives the rotated
// result, plastic returns included.
TEST(MohrCoulomb, RotatedInputGivesRotatedResult) {
  for (const auto& p : {make(15e3, 32, 8), make(15e3, 32, 8, 5e3)}) {
    const MohrCoulomb model(p);
    std::mt19937 rng(2024);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int plastic = 0;
    for (int i = 0; i < 300; ++i) {
      MaterialState a;
      a.stress =
          rotate(diagonal6(-100e3 + 50e3 * u(rng), -100e3 + 50e3 * u(rng), -100e3 + 50e3 * u(rng)),
                 random_rotation(rng));
      a.void_ratio = 0.7;
      Vec6 d_eps;
      for (int j = 0; j < 6; ++j) d_eps[j] = 3e-3 * u(rng);
      const Mat3 q = random_rotation(rng);
      MaterialState b = a;
      b.stress = rotate(a.stress, q);
      ASSERT_TRUE(model.update(a, d_eps).ok);
      ASSERT_TRUE(model.update(b, rotate(d_eps, q)).ok);
      const Vec6 expected = rotate(a.stress, q);
      EXPECT_LE((b.stress - expected).norm(), 1e-9 * (1e5 + expected.norm()));
      EXPECT_NEAR(MohrCoulomb::plastic_shear_strain(b), MohrCoulomb::plastic_shear_strain(a),
                  1e-9 * MohrCoulomb::plastic_shear_strain(a) + 1e-18);
      EXPECT_NEAR(b.void_ratio, a.void_ratio, 1e-14);
      if (MohrCoulomb::plastic_shear_strain(a) > 0.0) ++plastic;
    }
    EXPECT_GT(plastic, 100);
  }
}

}  // namespace
}  // namespace pilempm
