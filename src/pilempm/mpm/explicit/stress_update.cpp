// The stress update of the explicit step, the third pass over the particles.
#include <fmt/format.h>
#include <omp.h>

#include <cmath>

#include "pilempm/mpm/explicit/solver.hpp"
#include "pilempm/mpm/in_plane_rotation.hpp"
#include "pilempm/mpm/particle_kinematics.hpp"

namespace pilempm::mpm {

// Volumetric-locking remedy: within each grid cell, the volumetric strain increments of the
// particles (by their position after the move) are replaced by their mean weighted by the
// particle volumes, Δε̄_v = Σ V_p Δε_v,p / Σ V_p; the deviatoric parts are kept. The difference
// goes equally to the in-plane normal components in plane strain (the out-of-plane strain stays
// zero) and to the three normal components in axisymmetry. Σ V Δε_v over a cell is unchanged, so
// the volume of the cell's particles changes as without smoothing. The sums per cell run
// serially in particle order (deterministic for any thread count).
template <class Kinematics>
void Solver::smooth_volumetric_increments(Kinematics&& kinematics) {
  const Particles& p = particles_;
  const auto count = static_cast<long>(p.size());
  const bool axisymmetric = settings_.geometry == Geometry::axisymmetric;
  const GridAxis& x_axis = grid_.x_axis();
  const GridAxis& y_axis = grid_.y_axis();
  const int cells_x = x_axis.cell_count();
  smoothed_.resize(p.size());
  cell_volume_.assign(static_cast<std::size_t>(cells_x * y_axis.cell_count()), 0.0);
  cell_strain_.assign(cell_volume_.size(), 0.0);
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (long i = 0; i < count; ++i) {
    SmoothedIncrement& smoothed = smoothed_[i];
    kinematics(i, smoothed.increment, smoothed.hoop_increment);
    const Vec2& x = p.position[i];
    smoothed.cell = y_axis.cell_of(x.y()) * cells_x + x_axis.cell_of(x.x());
  }
  for (std::size_t i = 0; i < p.size(); ++i) {
    const SmoothedIncrement& smoothed = smoothed_[i];
    const double volumetric = smoothed.increment.trace() + smoothed.hoop_increment;
    cell_volume_[smoothed.cell] += p.volume[i];
    cell_strain_[smoothed.cell] += p.volume[i] * volumetric;
  }
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (long i = 0; i < count; ++i) {
    SmoothedIncrement& smoothed = smoothed_[i];
    const double mean = cell_strain_[smoothed.cell] / cell_volume_[smoothed.cell];
    const double difference = mean - (smoothed.increment.trace() + smoothed.hoop_increment);
    const double share = difference / (axisymmetric ? 3.0 : 2.0);
    smoothed.increment(0, 0) += share;
    smoothed.increment(1, 1) += share;
    if (axisymmetric) smoothed.hoop_increment += share;
  }
}

void Solver::update_stress(double dt) {
  Particles& p = particles_;
  const auto count = static_cast<long>(p.size());
  const int nx = grid_.nx();
  const bool axisymmetric = settings_.geometry == Geometry::axisymmetric;
  const bool stretch_domains = settings_.shape_function == ShapeFunction::cpgimp;
  const bool smoothing = settings_.volumetric_smoothing;
  // Kinematics of particle i over the step: the in-plane increment L dt, with the velocity
  // gradient L_ab = Σ v_ia dS_i/dx_b, and the hoop increment v_r dt / r (axisymmetry).
  const NodeMotion* motion = node_motion_.data();
  auto kinematics = [&](long i, Mat2& increment, double& hoop_increment) {
    const FieldGradient gradient = gradient_at_particle(
        stencils_[i], nx, [motion](int n) -> const Vec2& { return motion[n].velocity; });
    increment << dt * gradient.dux_dx, dt * gradient.dux_dy, dt * gradient.duy_dx,
        dt * gradient.duy_dy;
    hoop_increment = axisymmetric ? dt * gradient.radial / start_radius_[i] : 0.0;
  };
  if (smoothing) smooth_volumetric_increments(kinematics);

  std::vector<StressUpdateTally>& tallies = reset_tallies(stress_update_tallies_);
#pragma omp parallel num_threads(threads_)
  {
    StressUpdateTally& tally = tallies[omp_get_thread_num()];
#pragma omp for schedule(static)
    for (long i = 0; i < count; ++i) {
      Mat2 increment;
      double hoop_increment;
      if (smoothing) {
        increment = smoothed_[i].increment;
        hoop_increment = smoothed_[i].hoop_increment;
      } else {
        kinematics(i, increment, hoop_increment);
      }
      Vec6 strain_increment;
      strain_increment << increment(0, 0), increment(1, 1), hoop_increment, 0.0, 0.0,
          kSqrt2 * 0.5 * (increment(0, 1) + increment(1, 0));

      // Jaumann rate: rotate the state by the spin increment W = skew(L) dt (about z), then
      // update it with the strain increment.
      MaterialState& state = p.state[i];
      const double spin = 0.5 * (increment(1, 0) - increment(0, 1));
      if (spin != 0.0)
        rotate_state_about_z(state, spin, models_[p.material[i]]->history_variables());
      const Vec6 stress_before = state.stress;
      const UpdateResult result = models_[p.material[i]]->update(state, strain_increment);
      if (!result.ok) {
        tally.failure.note(static_cast<std::size_t>(i), result.message);
        continue;
      }

      // F <- (I + L dt) F; F_33 <- (1 + Δε_θθ) F_33; V = det F V_0.
      Mat2& deformation = p.deformation_gradient[i];
      deformation = (Mat2::Identity() + increment) * deformation;
      p.out_of_plane_stretch[i] *= 1.0 + hoop_increment;
      const double volume_before = p.volume[i];
      const double jacobian = deformation.determinant();
      p.volume[i] = jacobian * p.out_of_plane_stretch[i] * p.initial_volume[i];
      // Strain work with the mean stress and mean volume over the step (trapezoidal rule).
      tally.strain_work += 0.25 * (volume_before + p.volume[i]) *
                           (stress_before + state.stress).dot(strain_increment);

      if (stretch_domains) {
        // cpGIMP: the domain's half-lengths follow the stretch V = sqrt(F F^T) along x and y
        // (2x2 square root: sqrt(B) = (B + sqrt(det B) I) / sqrt(tr B + 2 sqrt(det B))).
        const Mat2 left_cauchy_green = deformation * deformation.transpose();
        const double root_det = std::abs(jacobian);
        const double scale = 1.0 / std::sqrt(left_cauchy_green.trace() + 2.0 * root_det);
        p.half_size[i] =
            p.initial_half_size[i].cwiseProduct(Vec2((left_cauchy_green(0, 0) + root_det) * scale,
                                                     (left_cauchy_green(1, 1) + root_det) * scale));
      }
    }
  }
  ParticleFailure failure;
  for (const StressUpdateTally& tally : tallies) {
    energies_.internal += tally.strain_work;
    failure.merge(tally.failure);
  }
  if (failure.any())
    fail_at_particle(failure.particle, fmt::format("the stress update failed: {}", failure.reason));
}

}  // namespace pilempm::mpm
