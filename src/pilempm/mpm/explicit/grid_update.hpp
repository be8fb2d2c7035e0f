#pragma once
// The grid update of the explicit step: the nodal momentum balance with local damping, dashpots
// (absorbing boundaries) and the boundary conditions, node by node.
#include <cmath>
#include <vector>

#include "pilempm/mpm/explicit/scatter.hpp"
#include "pilempm/mpm/explicit/thread_tally.hpp"
#include "pilempm/mpm/grid.hpp"

namespace pilempm::mpm {

struct SolverSettings;

inline double sign(double value) {
  return value > 0.0 ? 1.0 : (value < 0.0 ? -1.0 : 0.0);
}

/// Local non-viscous damping (Cundall 1987) of one nodal force component: -α |f| sign(v).
inline double local_damping_force(double alpha, double force, double velocity) {
  return -alpha * std::abs(force) * sign(velocity);
}

/// The dashpot coefficients C [kg/s] per node and direction of the absorbing boundaries in the
/// settings (Lysmer & Kuhlemeyer 1969): ρ c over each side node's share of the side, times r in
/// axisymmetry. Both empty without absorbing boundaries.
void dashpot_coefficients(const Grid& grid, const SolverSettings& settings,
                          std::vector<double>& dashpot_x, std::vector<double>& dashpot_y);

/// The update of one node over a step of length dt, once its mass, momentum and force are summed.
class GridUpdate {
 public:
  /// `dashpot_x`, `dashpot_y`: per node, empty without absorbing boundaries. `extra_force`: per
  /// node a force added to the scattered one (the surface contact), or null.
  GridUpdate(Grid& grid, double local_damping, const std::vector<double>& dashpot_x,
             const std::vector<double>& dashpot_y, NodeMotion* motion, double dt,
             const Vec2* extra_force = nullptr)
      : nodes_(grid.nodes()),
        free_x_(grid.free_x().data()),
        free_y_(grid.free_y().data()),
        motion_(motion),
        alpha_(local_damping),
        absorbing_(!dashpot_x.empty()),
        dashpot_x_(dashpot_x.data()),
        dashpot_y_(dashpot_y.data()),
        dt_(dt),
        extra_force_(extra_force) {}

  /// v = p / m; v^L = v + (f + f_damping) dt / m, with a dashpot -C v^L taken implicitly; the
  /// boundary conditions; Δv = v^L - v for FLIP. A node without mass is set at rest.
  void node(long n, GridUpdateTally& tally) const {
    NodalFields& nodes = nodes_;
    const double* free_x = free_x_;
    const double* free_y = free_y_;
    const double dt = dt_;
    const double mass = nodes.mass[n];
    if (extra_force_) {
      nodes.force_x[n] += extra_force_[n].x();
      nodes.force_y[n] += extra_force_[n].y();
    }
    if (mass <= 0.0) {
      nodes.velocity_x[n] = nodes.velocity_y[n] = 0.0;
      nodes.velocity_change_x[n] = nodes.velocity_change_y[n] = 0.0;
      motion_[n] = NodeMotion{};
      return;
    }
    const double vx = nodes.momentum_x[n] / mass, vy = nodes.momentum_y[n] / mass;
    // Local non-viscous damping: f_damped = f - α |f| sign(v), per free component. A held
    // component does not move, so it takes none: else the damping of the load a support carries
    // (α |f| with the sign of the velocity mapped from the particles) would enter the support's
    // reaction and the damping's energy.
    const double damping_x = free_x[n] * local_damping_force(alpha_, nodes.force_x[n], vx);
    const double damping_y = free_y[n] * local_damping_force(alpha_, nodes.force_y[n], vy);
    // v^L = v + f dt / m, then the boundary conditions; Δv over the step for FLIP. A dashpot
    // -C v^L (absorbing boundary) is taken implicitly: v^L = (m v + f dt) / (m + C dt).
    double new_vx = vx + (nodes.force_x[n] + damping_x) * dt / mass;
    double new_vy = vy + (nodes.force_y[n] + damping_y) * dt / mass;
    if (absorbing_) {
      const double cx = dashpot_x_[n], cy = dashpot_y_[n];
      if (cx > 0.0) new_vx *= mass / (mass + cx * dt);
      if (cy > 0.0) new_vy *= mass / (mass + cy * dt);
      // Work of the dashpot force -C v^L over the step, with the mean velocity.
      tally.absorbed_work += 0.5 * dt * (cx * new_vx * (vx + new_vx) + cy * new_vy * (vy + new_vy));
    }
    // The constraint's force: what takes the free velocity to the held one.
    tally.reaction.x() += (1.0 - free_x[n]) * (-mass * new_vx / dt);
    tally.reaction.y() += (1.0 - free_y[n]) * (-mass * new_vy / dt);
    new_vx *= free_x[n];
    new_vy *= free_y[n];
    nodes.velocity_x[n] = new_vx;
    nodes.velocity_y[n] = new_vy;
    nodes.velocity_change_x[n] = new_vx - vx;
    nodes.velocity_change_y[n] = new_vy - vy;
    motion_[n] = {Vec2(new_vx, new_vy), Vec2(new_vx - vx, new_vy - vy)};
    // Work of the damping force over the step, with the mean of the old and new velocities.
    tally.damping_work -= 0.5 * dt * (damping_x * (vx + new_vx) + damping_y * (vy + new_vy));
    // The damping force on the soil.
    tally.damping_force.x() += damping_x;
    tally.damping_force.y() += damping_y;
  }

 private:
  NodalFields& nodes_;
  const double* free_x_;
  const double* free_y_;
  NodeMotion* motion_;
  double alpha_;
  bool absorbing_;
  const double* dashpot_x_;
  const double* dashpot_y_;
  double dt_;
  const Vec2* extra_force_;
};

}  // namespace pilempm::mpm
