#pragma once
// Builders for the set-ups the MPM tests share: a box with walls and a base, a block of particles.
// Each sets only what its name says; the tests set the rest themselves.
#include <cmath>

#include "pilempm/core/tensor.hpp"
#include "pilempm/mpm/grid.hpp"
#include "pilempm/mpm/particles.hpp"

namespace pilempm::mpm::test_support {

/// Roller walls on the left and right sides and a fixed base (the top stays free).
inline void set_walls_and_fixed_base(Grid& grid) {
  grid.set_boundary(Side::left, BoundaryCondition::roller);
  grid.set_boundary(Side::right, BoundaryCondition::roller);
  grid.set_boundary(Side::bottom, BoundaryCondition::fixed);
}

/// The fill of the block [x_min, x_max) x [y_min, y_max) with density ρ [kg/m^3]; the other fields
/// at RectangleFill's defaults (2 x 2 particles per cell, material 0, zero state and velocity).
inline RectangleFill block_fill(double x_min, double x_max, double y_min, double y_max,
                                double density) {
  RectangleFill fill;
  fill.x_min = x_min;
  fill.x_max = x_max;
  fill.y_min = y_min;
  fill.y_max = y_max;
  fill.density = density;
  return fill;
}

/// The particles of one block fill on the grid.
inline Particles particle_block(const Grid& grid, Geometry geometry, const RectangleFill& fill) {
  Particles particles;
  fill_rectangle(particles, grid, geometry, fill);
  return particles;
}

/// A block of density ρ with its top at y = `top` on a plane inclined by θ, in the frame of the
/// plane (gravity g cos θ along −y from the solver): the geostatic stress σ_yy = −ρ g cos θ
/// (top − y), σ_xx = σ_zz = K0 σ_yy with K0 = ν / (1 − ν), and g sin θ along +x as a load on each
/// particle.
inline void set_geostatic_on_plane(Particles& particles, double density, double gravity,
                                   double angle, double top, double poisson) {
  const double k0 = poisson / (1.0 - poisson);
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const double vertical =
        -density * gravity * std::cos(angle) * (top - particles.position[p].y());
    particles.state[p].stress[k22] = vertical;
    particles.state[p].stress[k11] = particles.state[p].stress[k33] = k0 * vertical;
    particles.external_force[p] = Vec2(particles.mass[p] * gravity * std::sin(angle), 0.0);
  }
}

}  // namespace pilempm::mpm::test_support
