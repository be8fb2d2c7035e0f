#pragma once
// Grid to particles, the second pass of the explicit step: the FLIP/PIC (or XPIC) velocity and
// the position of each particle from the updated grid.
#include <algorithm>

#include "pilempm/mpm/explicit/scatter.hpp"
#include "pilempm/mpm/explicit/thread_tally.hpp"
#include "pilempm/mpm/grid.hpp"
#include "pilempm/mpm/particles.hpp"
#include "pilempm/mpm/stencil_visit.hpp"

namespace pilempm::mpm {

class GridToParticles {
 public:
  /// `stencils`: the weights at x^n; `xpic_shift`: v* - v^n per node with XPIC(m > 1), else null.
  GridToParticles(Particles& particles, const Grid& grid, const Stencil* stencils,
                  const NodeMotion* motion, const Vec2* xpic_shift, double flip_fraction,
                  double mass_scaling, bool axisymmetric, const Vec2& gravity, double dt)
      : particles_(particles),
        grid_(grid),
        stencils_(stencils),
        motion_(motion),
        xpic_shift_(xpic_shift),
        nx_(grid.nx()),
        flip_(flip_fraction),
        mass_scaling_(mass_scaling),
        axisymmetric_(axisymmetric),
        gravity_(gravity),
        dt_(dt) {}

  /// Moves particle i: V = flip (V + S Δv) + (1 - flip) S v_PIC, x += dt S v^L; adds its
  /// external work, kinetic energy and speed to the tally (and notes it there if it left the
  /// grid). Returns its new momentum (inertial mass).
  Vec2 move(long i, ParticleMotionTally& tally) const {
    Particles& p = particles_;
    const NodeMotion* motion = motion_;
    Vec2 grid_velocity = Vec2::Zero(), velocity_change = Vec2::Zero();
    for_each_node(stencils_[i], nx_, [&](int n, double s, double, double) {
      const NodeMotion& node = motion[n];
      grid_velocity += s * node.velocity;
      velocity_change += s * node.change;
    });
    // The PIC share's target: the grid velocity, with XPIC(m) shifted by S (v* - v^n).
    Vec2 pic_velocity = grid_velocity;
    if (xpic_shift_) {
      const Vec2* shift = xpic_shift_;
      for_each_node(stencils_[i], nx_,
                    [&](int n, double s, double, double) { pic_velocity += s * shift[n]; });
    }
    // FLIP/PIC blend of the particle velocity; the particle moves with the grid velocity.
    p.velocity[i] = flip_ * (p.velocity[i] + velocity_change) + (1.0 - flip_) * pic_velocity;
    const Vec2 displacement = dt_ * grid_velocity;
    tally.external_work += (p.mass[i] * gravity_ + p.external_force[i]).dot(displacement);
    p.position[i] += displacement;
    const double inertial_mass = mass_scaling_ * p.mass[i];
    // |v|^2: the largest speed is the root of the largest square (taken after the loop).
    const double squared_speed = p.velocity[i].squaredNorm();
    tally.kinetic_energy += 0.5 * inertial_mass * squared_speed;
    tally.max_squared_speed = std::max(tally.max_squared_speed, squared_speed);
    const Vec2& x = p.position[i];
    if (!(p.velocity[i].allFinite() && grid_.contains(x.x(), x.y()) &&
          (!axisymmetric_ || x.x() > 0.0)))
      tally.failure.note(static_cast<std::size_t>(i),
                         "the particle left the grid (or reached r <= 0) or its velocity is not "
                         "finite");
    return inertial_mass * p.velocity[i];
  }

 private:
  Particles& particles_;
  const Grid& grid_;
  const Stencil* stencils_;
  const NodeMotion* motion_;
  const Vec2* xpic_shift_;
  int nx_;
  double flip_;
  double mass_scaling_;
  bool axisymmetric_;
  Vec2 gravity_;
  double dt_;
};

}  // namespace pilempm::mpm
