// The quasi-static solver's per-iterate work: the evaluation of an iterate (strains, stresses and
// tangents, internal, external and contact forces, the residual and the Newton matrix on the
// sub-increment's pattern, step_setup.cpp).
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/mpm/in_plane_rotation.hpp"
#include "pilempm/mpm/quasi_static/midpoint_strain.hpp"
#include "pilempm/mpm/quasi_static/step_data.hpp"

namespace pilempm::mpm::quasi_static {

using namespace detail;

namespace {

// The isotropic elastic stiffness (ν = kFallbackPoisson) of a constrained modulus M:
// E = M (1 + ν)(1 − 2ν) / (1 − ν).
Mat6 isotropic_stiffness(double constrained_modulus) {
  const double nu = kFallbackPoisson;
  return ElasticParameters{constrained_modulus * (1.0 + nu) * (1.0 - 2.0 * nu) / (1.0 - nu), nu}
      .stiffness();
}

// Where a particle's material tangent came from (material_tangent).
enum class TangentSource {
  closed_form,   // the floor's, the rate form's or the model's own: cheap
  perturbation,  // differences of the integrated update: the costly case
  reused,        // the one given, computed earlier in the sub-increment (Settings::tangent_reuse)
};

// The material part of a particle's Newton matrix d (in-plane): the derivative of its integrated
// update `state` (from `rotated` over `strain`) with respect to the strain. Where it would be
// differentiated (no closed form), `reusable`, where given, is taken instead. `fixed`: where the
// update ended with a stress that no longer changes with the strain (Trial::fixed_stress).
TangentSource material_tangent(const ConstitutiveModel& model, const MaterialState& converged,
                               const MaterialState& rotated, const MaterialState& state,
                               const Vec6& strain, char fixed, double reference_modulus,
                               const SubstepPath& path, const Settings& settings, bool axisymmetric,
                               const Mat4* reusable, Mat4& d) {
  // On the stress floor or at an apex the integrated update does not change with the strain (a
  // zero derivative would leave the nodes such particles alone support without stiffness): a
  // small isotropic elastic stiffness instead, in the matrix only, of the material's reference
  // modulus (a stress-free hypoplastic particle's own is 10⁻³ of it): Settings::floor_stiffness
  // of it on the floor, Settings::apex_stiffness at an apex.
  const auto elastic_fallback = [&] {
    const double fraction = fixed == kAtApex ? settings.apex_stiffness : settings.floor_stiffness;
    d = in_plane(
        isotropic_stiffness(fraction * std::max(model.wave_modulus(converged), reference_modulus)));
  };
  if (fixed != kNotFixed) {
    elastic_fallback();
    return TangentSource::closed_form;
  }
  const TangentKind kind = settings.tangent;
  if (kind == TangentKind::elastic) {
    d = in_plane(model.tangent(state, strain));
    return TangentSource::closed_form;
  }
  // The model's own consistent tangent where it has one in closed form (linear elasticity,
  // Mohr-Coulomb), from the same start as the update.
  Mat6 consistent;
  if (kind == TangentKind::automatic && model.consistent_tangent(rotated, strain, consistent)) {
    d = in_plane(consistent);
    return TangentSource::closed_form;
  }
  if (reusable != nullptr) {
    d = *reusable;
    return TangentSource::reused;
  }
  // Fellin & Ostermann (2002): forward differences of the integrated update, the probes along
  // the sub-steps the update took (SubstepPath: the quotient is then the derivative of one
  // smooth map, and the probes need no error control). The strain components that vary
  // (columns of d): plane strain has no 33.
  const int used_columns = axisymmetric ? 4 : 3;
  const int used_column[4] = {0, 1, axisymmetric ? 2 : 3, 3};
  const double h = settings.perturbation * std::max(strain.norm(), 1.0e-6);
  for (int c = 0; c < used_columns; ++c) {
    const int dc = used_column[c];
    Vec6 perturbed = strain;
    perturbed[kComponents[dc]] += h;
    MaterialState probe = rotated;
    if (!model.update_along(probe, perturbed, path).ok) {  // beyond the model's domain
      elastic_fallback();
      return TangentSource::closed_form;
    }
    const Vec6 difference = (probe.stress - state.stress) / h;
    for (int r = 0; r < 4; ++r) d(r, dc) = difference[kComponents[r]];
  }
  return TangentSource::perturbation;
}

}  // namespace

bool QuasiStaticSolver::evaluate(const StepSetup& setup, const std::vector<double>& du,
                                 double gravity, double traction,
                                 const std::vector<Vec2>& body_step, bool tangent, Trial& trial,
                                 LoadStepResult& result, TangentCache* cache) const {
  const Particles& p = particles_;
  const long count = static_cast<long>(p.size());
  const int nodes = grid_.node_count();
  const bool axisymmetric = settings_.geometry == Geometry::axisymmetric;
  const bool first_matrix =
      tangent && std::all_of(du.begin(), du.end(), [](double v) { return v == 0.0; });
  const auto material_start = std::chrono::steady_clock::now();

  // The iterate this trial was last evaluated at, evaluated again for its matrix: its stresses
  // stand (the model updates are not repeated, only the tangents are added).
  bool reuse_states = tangent && trial.has_states &&
                      trial.fixed_stress.size() == std::size_t(count) &&
                      trial.node_displacement.size() == std::size_t(nodes);
  for (int n = 0; n < nodes && reuse_states; ++n)
    for (int c = 0; c < 2; ++c) {
      const int d = setup.dof[2 * std::size_t(n) + std::size_t(c)];
      if (trial.node_displacement[std::size_t(n)][c] != (d >= 0 ? du[std::size_t(d)] : 0.0))
        reuse_states = false;
    }
  trial.has_states = false;
  trial.node_displacement.assign(std::size_t(nodes), Vec2::Zero());
  for (int n = 0; n < nodes; ++n)
    for (int c = 0; c < 2; ++c) {
      const int d = setup.dof[2 * std::size_t(n) + std::size_t(c)];
      if (d >= 0) trial.node_displacement[std::size_t(n)][c] = du[std::size_t(d)];
    }
  trial.state.resize(std::size_t(count));
  trial.path.resize(std::size_t(count));
  trial.fixed_stress.resize(std::size_t(count));
  trial.strain_increment.resize(std::size_t(count));
  // Empty without the low-stress stabilisation (the common case): nothing to add per particle.
  const bool stabilising = stabilisation_on() && stabilisation_scale_ > 0.0;
  trial.stabilising_stress.assign(stabilising ? std::size_t(count) : 0, Vec6::Zero());
  trial.gradient.resize(std::size_t(count));
  trial.hoop.resize(std::size_t(count));
  if (tangent) {
    trial.tangent.resize(std::size_t(count));
    trial.spin_tangent.resize(std::size_t(count));
  }
  // Tangents computed earlier in the sub-increment (Settings::tangent_reuse).
  const double reuse = settings_.tangent_reuse;
  if (!tangent || !(reuse > 0.0)) cache = nullptr;
  if (cache != nullptr && cache->valid.size() != std::size_t(count)) {
    cache->tangent.resize(std::size_t(count));
    cache->strain.resize(std::size_t(count));
    cache->spin.resize(std::size_t(count));
    cache->valid.assign(std::size_t(count), 0);
  }
  int reused_tangents = 0;

  // Kinematics, the stress from the converged state and the tangent, particle by particle.
  bool failed = false;
  trial.failed_particle = -1;
  trial.failure = "";
  int floor_particles = 0;
  // The added modulus of the low-stress stabilisation (Settings::low_stress_stiffness), from the
  // converged mean stress: fixed over the sub-increment's iterations.
  const auto low_stress_modulus = [&](long i) {
    if (!stabilising) return 0.0;
    const double weight =
        1.0 - mean_stress(p.state[std::size_t(i)].stress) / settings_.low_stress_pressure;
    return std::clamp(weight, 0.0, 1.0) * settings_.low_stress_stiffness * stabilisation_scale_ *
           contact_modulus_[std::size_t(p.material[std::size_t(i)])];
  };
  const bool averaging = settings_.volumetric_averaging;
  const bool midpoint = settings_.midpoint_strain;
  const double normal_components = axisymmetric ? 3.0 : 2.0;
  // The share of the reference's body motion this sub-increment repeats (signed; 0 without).
  double repeat = 0.0;
  if (stabilising && !reference_strain_.empty() && reference_motion_.squaredNorm() > 0.0)
    repeat = largest_motion(body_step).dot(reference_motion_) / reference_motion_.squaredNorm();
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads_) reduction(|| : failed) \
    reduction(+ : floor_particles, reused_tangents)
  for (long i = 0; i < count; ++i) {
    const ParticleNodes& pn = setup.nodes[std::size_t(i)];
    Mat2 gradient = Mat2::Zero();
    double radial = 0.0;
    for (int k = 0; k < pn.count; ++k) {
      const Vec2& u = trial.node_displacement[std::size_t(pn.node[k])];
      gradient += u * pn.gradient[k].transpose();
      radial += pn.weight[k] * u.x();
    }
    const double hoop = axisymmetric ? radial / p.position[std::size_t(i)].x() : 0.0;
    Vec6 strain;
    strain << gradient(0, 0), gradient(1, 1), hoop, 0.0, 0.0,
        kSqrt2 * 0.5 * (gradient(0, 1) + gradient(1, 0));
    if (averaging) {  // the cell's mean volumetric increment replaces the particle's own
      const StepSetup::CellMean& mean = setup.cells[std::size_t(setup.cell[std::size_t(i)])];
      double mean_volumetric = 0.0;
      for (int j = 0; j < mean.count; ++j)
        mean_volumetric += mean.row[j].dot(trial.node_displacement[std::size_t(mean.node[j])]);
      const double correction =
          (mean_volumetric - (strain[k11] + strain[k22] + strain[k33])) / normal_components;
      strain[k11] += correction;
      strain[k22] += correction;
      if (axisymmetric) strain[k33] += correction;
    }
    double spin = 0.5 * (gradient(1, 0) - gradient(0, 1));
    // The increments on the midpoint configuration (Settings::midpoint_strain), and their
    // derivative with respect to the linear ones, for the Newton matrix's chain rule.
    detail::Mat5 midpoint_jacobian;
    if (midpoint) {
      detail::Vec5 linear;
      linear << strain[k11], strain[k22], strain[k33], strain[k12], spin;
      if (!detail::has_midpoint(linear)) {
        failed = true;
        trial.record_failure(i, "the iterate turns the particle inside out");
        continue;
      }
      const detail::Vec5 mid =
          detail::midpoint_increments(linear, tangent ? &midpoint_jacobian : nullptr);
      strain[k11] = mid[0];
      strain[k22] = mid[1];
      strain[k33] = mid[2];
      strain[k12] = mid[3];
      spin = mid[4];
    }
    trial.gradient[std::size_t(i)] = gradient;
    trial.hoop[std::size_t(i)] = hoop;
    trial.strain_increment[std::size_t(i)] = strain;
    // Hughes-Winget: rotate the converged state by the spin, then integrate the increment.
    MaterialState rotated = p.state[std::size_t(i)];
    const ConstitutiveModel& model = *materials_[std::size_t(p.material[std::size_t(i)])];
    if (spin != 0.0) rotate_state_about_z(rotated, spin, model.history_variables());
    MaterialState& state = trial.state[std::size_t(i)];
    if (!reuse_states) {
      state = rotated;
      const UpdateResult update = model.update_recording(state, strain, trial.path[std::size_t(i)]);
      if (!update.ok) {
        failed = true;
        trial.record_failure(i, update.message);
        continue;
      }
      trial.fixed_stress[std::size_t(i)] = update.mean_stress_floor_hits > 0 ? kOnFloor
                                           : update.at_apex                  ? kAtApex
                                                                             : kNotFixed;
    }
    const bool fixed = trial.fixed_stress[std::size_t(i)] != kNotFixed;
    if (fixed) ++floor_particles;
    // Low-stress stabilisation (Settings::low_stress_stiffness): weighted by the converged mean
    // stress, so the set and the weights stay fixed over the sub-increment's iterations.
    const double low_modulus = low_stress_modulus(i);
    Mat6 low_stiffness = Mat6::Zero();
    if (low_modulus > 0.0) {
      low_stiffness = isotropic_stiffness(low_modulus);
      const Vec6 reference =
          repeat != 0.0 ? Vec6(repeat * reference_strain_[std::size_t(i)]) : Vec6::Zero();
      trial.stabilising_stress[std::size_t(i)] = low_stiffness * (strain - reference);
    }
    if (!tangent) continue;
    Mat4& d = trial.tangent[std::size_t(i)];
    d.setZero();
    // The tangent differentiated at an earlier iterate of the sub-increment stands in where the
    // particle's strain and spin increments have since changed by at most `reuse` of the strain
    // increment's norm.
    const Mat4* reusable = nullptr;
    if (cache != nullptr && cache->valid[std::size_t(i)] != 0) {
      const double spin_change = spin - cache->spin[std::size_t(i)];
      const double change =
          (strain - cache->strain[std::size_t(i)]).squaredNorm() + 2.0 * spin_change * spin_change;
      if (change <= reuse * reuse * strain.squaredNorm())
        reusable = &cache->tangent[std::size_t(i)];
    }
    const TangentSource source = material_tangent(
        model, p.state[std::size_t(i)], rotated, state, strain, trial.fixed_stress[std::size_t(i)],
        contact_modulus_[std::size_t(p.material[std::size_t(i)])], trial.path[std::size_t(i)],
        settings_, axisymmetric, reusable, d);
    if (source == TangentSource::reused) {
      ++reused_tangents;
    } else if (cache != nullptr) {  // only a differentiated tangent is kept for reuse
      const bool keep = source == TangentSource::perturbation;
      cache->valid[std::size_t(i)] = keep ? 1 : 0;
      if (keep) {
        cache->tangent[std::size_t(i)] = d;
        cache->strain[std::size_t(i)] = strain;
        cache->spin[std::size_t(i)] = spin;
      }
    }
    if (low_modulus > 0.0) d += in_plane(low_stiffness);
    // The spin terms (Settings::spin_terms): ∂σ/∂w = (∂σ/∂σ_start) ∂(R σ_n Rᵀ)/∂w with
    // ∂σ/∂σ_start taken as the identity (exact for linear elasticity; for the other models the
    // increment's dependence on its start stress is left out). A particle on the stress floor
    // has the floor stiffness alone (material_tangent).
    Vec4& spin_column = trial.spin_tangent[std::size_t(i)];
    spin_column.setZero();
    if (settings_.spin_terms && !fixed) {
      const Vec6 turn = rotation_derivative_about_z(rotated.stress, spin);
      for (int r = 0; r < 4; ++r) spin_column[r] = turn[kComponents[r]];
    }
    if (midpoint) {  // the stress's derivative with respect to the linear increments
      Eigen::Matrix<double, 4, 5> chained;
      chained.leftCols<4>() = d;
      chained.col(4) = spin_column;
      chained = (chained * midpoint_jacobian).eval();
      d = chained.leftCols<4>();
      spin_column = chained.col(4);
    }
  }
  result.seconds_material += seconds_since(material_start);
  result.reused_tangents += reused_tangents;
  trial.floor_particles = floor_particles;
  if (failed) return false;

  // Assembly: internal and external forces, the material stiffness, particle by particle into
  // per-thread arrays (the first thread's are the trial's own), summed after.
  const auto assembly_start = std::chrono::steady_clock::now();
  const std::size_t components = 2 * std::size_t(nodes);
  const std::size_t entries = tangent ? std::size_t(setup.pattern.nonZeros()) : 0;
  trial.internal.assign(components, 0.0);
  trial.external.assign(components, 0.0);
  trial.contact.assign(components, 0.0);
  trial.material_values.assign(entries, 0.0);
  trial.contact_entries.clear();
  trial.ghost_entries.clear();
  trial.has_matrix = tangent;
  const double body_force = -gravity * settings_.gravity;
  std::vector<std::vector<double>> extra_internal, extra_external, extra_values;
#pragma omp parallel num_threads(threads_)
  {
    const int thread = omp_get_thread_num();
#pragma omp single
    {
      const std::size_t extra = std::size_t(std::max(omp_get_num_threads() - 1, 0));
      extra_internal.resize(extra);
      extra_external.resize(extra);
      extra_values.resize(extra);
    }
    if (thread > 0) {
      extra_internal[std::size_t(thread - 1)].assign(components, 0.0);
      extra_external[std::size_t(thread - 1)].assign(components, 0.0);
      extra_values[std::size_t(thread - 1)].assign(entries, 0.0);
    }
#pragma omp barrier
    double* internal =
        thread == 0 ? trial.internal.data() : extra_internal[std::size_t(thread - 1)].data();
    double* external =
        thread == 0 ? trial.external.data() : extra_external[std::size_t(thread - 1)].data();
    double* values =
        thread == 0 ? trial.material_values.data() : extra_values[std::size_t(thread - 1)].data();
    // B (4 rows, 2 columns per node) over the particle's nodes, or with volumetric averaging
    // B̄ = B + m (b̄ − b_p)^T / n over the nodes of its cell (m: ones in the normal rows, b_p the
    // particle's volumetric row, b̄ the cell's mean, n = 2 in plane strain, 3 in axisymmetry).
    Eigen::Matrix<double, 4, 2 * kMaxCellNodes> b;
    Eigen::Matrix<double, 4, 2 * kMaxCellNodes> db;
    Eigen::Matrix<double, 1, 2 * kMaxCellNodes> spin_row;  // ∂w/∂u over the block's columns
#pragma omp for schedule(static)
    for (long i = 0; i < count; ++i) {
      const ParticleNodes& pn = setup.nodes[std::size_t(i)];
      const double volume = p.volume[std::size_t(i)];
      // The model's stress and the low-stress stabilisation's, where there is one.
      Vec6 s = trial.state[std::size_t(i)].stress;
      if (stabilising) s += trial.stabilising_stress[std::size_t(i)];
      const double radius = p.position[std::size_t(i)].x();
      const Vec2 load = traction * p.external_force[std::size_t(i)] +
                        Vec2(0.0, p.mass[std::size_t(i)] * body_force);
      const StepSetup::CellMean* mean =
          averaging ? &setup.cells[std::size_t(setup.cell[std::size_t(i)])] : nullptr;
      int width = 0;
      const int* column_node = setup.block_nodes(setup.block[std::size_t(i)], width);
      b.leftCols(2 * width).setZero();
      spin_row.leftCols(2 * width).setZero();
      for (int k = 0; k < pn.count; ++k) {
        const int j = mean != nullptr ? setup.slot[std::size_t(i)][std::size_t(k)] : k;
        const Vec2& g = pn.gradient[k];
        spin_row(2 * j) = -0.5 * g.y();
        spin_row(2 * j + 1) = 0.5 * g.x();
        b(0, 2 * j) = g.x();
        b(1, 2 * j + 1) = g.y();
        if (axisymmetric) b(2, 2 * j) = pn.weight[k] / radius;
        b(3, 2 * j) = g.y() / kSqrt2;
        b(3, 2 * j + 1) = g.x() / kSqrt2;
      }
      if (mean != nullptr)
        for (int j = 0; j < width; ++j)
          for (int c = 0; c < 2; ++c) {
            const double own = b(0, 2 * j + c) + b(1, 2 * j + c) + b(2, 2 * j + c);
            const double correction = (mean->row[j][c] - own) / normal_components;
            b(0, 2 * j + c) += correction;
            b(1, 2 * j + c) += correction;
            if (axisymmetric) b(2, 2 * j + c) += correction;
          }
      const Vec4 stress4(s[k11], s[k22], s[k33], s[k12]);
      for (int j = 0; j < width; ++j) {
        const std::size_t n = std::size_t(column_node[j]);
        internal[2 * n] += volume * b.col(2 * j).dot(stress4);
        internal[2 * n + 1] += volume * b.col(2 * j + 1).dot(stress4);
      }
      for (int k = 0; k < pn.count; ++k) {
        const std::size_t n = std::size_t(pn.node[k]);
        external[2 * n] += pn.weight[k] * load.x();
        external[2 * n + 1] += pn.weight[k] * load.y();
      }
      if (!tangent) continue;
      const int columns = 2 * width;
      db.leftCols(columns).noalias() = volume * trial.tangent[std::size_t(i)] * b.leftCols(columns);
      db.leftCols(columns).noalias() +=
          volume * trial.spin_tangent[std::size_t(i)] * spin_row.leftCols(columns);
      const int* map =
          setup.scatter.data() + setup.scatter_offset[std::size_t(setup.block[std::size_t(i)])];
      for (int c = 0; c < columns; ++c)
        for (int r = 0; r < columns; ++r) {
          const int at = map[c * columns + r];
          if (at >= 0) values[at] += b.col(r).dot(db.col(c));
        }
    }
    // The other threads' shares, summed over index ranges in parallel.
    if (!extra_internal.empty()) {
#pragma omp for schedule(static)
      for (long c = 0; c < long(components); ++c)
        for (std::size_t t = 0; t < extra_internal.size(); ++t) {
          trial.internal[std::size_t(c)] += extra_internal[t][std::size_t(c)];
          trial.external[std::size_t(c)] += extra_external[t][std::size_t(c)];
        }
#pragma omp for schedule(static)
      for (long e = 0; e < long(entries); ++e)
        for (std::size_t t = 0; t < extra_values.size(); ++t)
          trial.material_values[std::size_t(e)] += extra_values[t][std::size_t(e)];
    }
  }

  // Contact at the corners of the particles' domains against the bodies' exact surfaces.
  trial.corner.assign(std::size_t(count) * kCorners, PointContact{});
  trial.corner_body.assign(std::size_t(count) * kCorners, -1);
  trial.corner_part.assign(std::size_t(count) * kCorners, 0);
  trial.corner_gap.assign(std::size_t(count) * kCorners, 0.0);
  for (long i = 0; i < count && !bodies_.empty(); ++i) {
    if (!setup.near_body[std::size_t(i)]) continue;
    const ParticleNodes& pn = setup.nodes[std::size_t(i)];
    const Vec2& x = p.position[std::size_t(i)];
    const Vec2& l = p.half_size[std::size_t(i)];
    const double modulus = contact_modulus_[std::size_t(p.material[std::size_t(i)])];
    const double size = penalty_length(p.initial_half_size[std::size_t(i)]);
    for (int q = 0; q < kCorners; ++q) {
      // The corners are contact points that move with the particle's affine motion (material
      // points of their own, so that a converged gap carries over to the next step unchanged):
      // Δu_q = Σ_k c_k Δu_k, c_k = S_k + ∇S_k · (x_q - x_p).
      const Vec2 corner = corner_position_[std::size_t(i) * kCorners + std::size_t(q)];
      const Vec2 offset = corner - x;
      double coefficient[16];
      Vec2 moved = Vec2::Zero();
      for (int k = 0; k < pn.count; ++k) {
        coefficient[k] = pn.weight[k] + pn.gradient[k].dot(offset);
        moved += coefficient[k] * trial.node_displacement[std::size_t(pn.node[k])];
      }
      const double normal_stiffness =
          corner_normal_stiffness(settings_.contact.penalty_factor, modulus, l, size,
                                  axisymmetric ? std::abs(corner.x()) : 1.0);
      // Points this close outside keep the stick stiffness in the matrix (see penalty_contact).
      // Only in the first matrix of an increment: later on it would be a spring without force.
      const double margin = first_matrix ? settings_.contact.stiffness_margin * size : 0.0;
      const std::size_t index = std::size_t(i) * kCorners + std::size_t(q);
      for (std::size_t body = 0; body < bodies_.size(); ++body) {
        const Vec2 body_move = body < body_step.size() ? body_step[body] : Vec2::Zero();
        const SurfaceQuery hit = setup.surfaces[body].query(corner + moved - body_move);
        if (!(hit.distance < margin)) continue;
        const ContactHistory& history = contact_history_[index];
        const Vec2 previous =
            history.body == static_cast<int>(body) ? history.tangential_force : Vec2::Zero();
        const PointContact point =
            penalty_contact(hit.distance, hit.normal, moved - body_move, previous, normal_stiffness,
                            settings_.contact.tangential_ratio * normal_stiffness,
                            bodies_[body].friction(), margin, settings_.contact.smoothing * size,
                            settings_.contact.turning_terms ? hit.curvature : 0.0);
        if (point.active) {
          trial.corner[index] = point;
          trial.corner_body[index] = static_cast<int>(body);
          trial.corner_part[index] = hit.part;
          trial.corner_gap[index] = hit.distance;
          for (int k = 0; k < pn.count; ++k) {
            const std::size_t n = std::size_t(pn.node[k]);
            trial.contact[2 * n] += coefficient[k] * point.force.x();
            trial.contact[2 * n + 1] += coefficient[k] * point.force.y();
          }
        }
        if (tangent) {
          int width = 0;
          setup.block_nodes(setup.block[std::size_t(i)], width);
          const int* map =
              setup.scatter.data() + setup.scatter_offset[std::size_t(setup.block[std::size_t(i)])];
          const auto local = [&](int k) {
            return averaging ? setup.slot[std::size_t(i)][std::size_t(k)] : k;
          };
          for (int a = 0; a < pn.count; ++a)
            for (int c = 0; c < pn.count; ++c) {
              const Mat2 block = coefficient[a] * coefficient[c] * point.stiffness;
              for (int r = 0; r < 2; ++r)
                for (int s = 0; s < 2; ++s) {
                  const int at = map[(2 * local(c) + s) * 2 * width + 2 * local(a) + r];
                  if (at < 0) continue;
                  trial.contact_entries.push_back(
                      {at, setup.dof[2 * std::size_t(pn.node[a]) + std::size_t(r)],
                       setup.dof[2 * std::size_t(pn.node[c]) + std::size_t(s)], block(r, s)});
                }
            }
        }
        break;  // one body per corner
      }
    }
  }

  // Ghost springs between weakly supported nodes and their neighbours (internal forces).
  for (std::size_t g = 0; g < setup.ghosts.size(); ++g) {
    const StepSetup::GhostSpring& ghost = setup.ghosts[g];
    const Vec2 stretch = trial.node_displacement[std::size_t(ghost.node_a)] -
                         trial.node_displacement[std::size_t(ghost.node_b)];
    for (int c = 0; c < 2; ++c) {
      const std::size_t ca = 2 * std::size_t(ghost.node_a) + std::size_t(c);
      const std::size_t cb = 2 * std::size_t(ghost.node_b) + std::size_t(c);
      trial.internal[ca] += ghost.stiffness * stretch[c];
      trial.internal[cb] -= ghost.stiffness * stretch[c];
      if (!tangent) continue;
      const int da = setup.dof[ca], db = setup.dof[cb];
      const std::array<int, 4>& at = setup.ghost_entry[2 * g + std::size_t(c)];
      if (da >= 0) trial.ghost_entries.push_back({at[0], da, da, ghost.stiffness});
      if (db >= 0) trial.ghost_entries.push_back({at[1], db, db, ghost.stiffness});
      if (da >= 0 && db >= 0) {
        trial.ghost_entries.push_back({at[2], da, db, -ghost.stiffness});
        trial.ghost_entries.push_back({at[3], db, da, -ghost.stiffness});
      }
    }
  }
  trial.residual.setZero(setup.unknowns);
  double internal_norm = 0.0, external_norm = 0.0, contact_norm = 0.0;
  for (std::size_t c = 0; c < 2 * std::size_t(nodes); ++c) {
    if (!setup.active[c / 2]) continue;
    internal_norm += trial.internal[c] * trial.internal[c];
    external_norm += trial.external[c] * trial.external[c];
    contact_norm += trial.contact[c] * trial.contact[c];
    const int d = setup.dof[c];
    if (d >= 0) trial.residual[d] = trial.internal[c] - trial.external[c] - trial.contact[c];
  }
  trial.reference_force = std::sqrt(std::max({internal_norm, external_norm, contact_norm}));
  result.seconds_assembly += seconds_since(assembly_start);
  trial.has_states = trial.residual.allFinite();
  return trial.has_states;
}

}  // namespace pilempm::mpm::quasi_static
