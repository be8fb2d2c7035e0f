#pragma once
// The MUSL remap (Sulsky, Zhou & Schreyer 1995): the particles' new momentum straight back to the
// grid, with the weights of the step, and the nodal velocities from it with the boundary
// conditions. The stress update then takes its velocity gradient from these velocities.
#include "pilempm/mpm/explicit/scatter.hpp"
#include "pilempm/mpm/grid.hpp"
#include "pilempm/mpm/stencil_visit.hpp"

namespace pilempm::mpm {

class MuslRemap {
 public:
  MuslRemap(Grid& grid, const Stencil* stencils, NodeMotion* motion)
      : nodes_(grid.nodes()),
        free_x_(grid.free_x().data()),
        free_y_(grid.free_y().data()),
        stencils_(stencils),
        motion_(motion),
        nx_(grid.nx()) {}

  /// Particle i's new momentum into a thread's sums.
  void scatter(long i, const Vec2& momentum, NodeSums* to) const {
    for_each_node(stencils_[i], nx_,
                  [&](int n, double s, double, double) { to[n].momentum += s * momentum; });
  }

  /// The velocity of node n from its remapped momentum, with the boundary conditions.
  void node(long n) const {
    NodalFields& nodes = nodes_;
    const double mass = nodes.mass[n];
    const double inverse_mass = mass > 0.0 ? 1.0 / mass : 0.0;
    const double vx = free_x_[n] * nodes.momentum_x[n] * inverse_mass;
    const double vy = free_y_[n] * nodes.momentum_y[n] * inverse_mass;
    nodes.velocity_x[n] = vx;
    nodes.velocity_y[n] = vy;
    motion_[n].velocity = Vec2(vx, vy);
  }

 private:
  NodalFields& nodes_;
  const double* free_x_;
  const double* free_y_;
  const Stencil* stencils_;
  NodeMotion* motion_;
  int nx_;
};

}  // namespace pilempm::mpm
