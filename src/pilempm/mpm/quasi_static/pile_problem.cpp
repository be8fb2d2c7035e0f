#include "pilempm/mpm/quasi_static/pile_problem.hpp"

#include <cmath>

namespace pilempm::mpm::quasi_static {

QuasiStaticSolver PileProblem::build() const {
  const double h = diameter / cells_per_d;
  const int radial_cells = static_cast<int>(std::lround(width_in_d * cells_per_d));
  const int vertical_cells = static_cast<int>(std::lround(height_in_d * cells_per_d));
  // Cells above the surface for the heave.
  Grid grid(GridAxis::uniform(0.0, radial_cells * h, radial_cells),
            GridAxis::uniform(0.0, (vertical_cells + 2) * h, vertical_cells + 2));
  grid.set_boundary(Side::right, BoundaryCondition::roller);
  grid.set_boundary(Side::bottom, BoundaryCondition::fixed);
  Particles particles;
  RectangleFill fill;
  fill.x_min = 0.0;
  fill.x_max = radial_cells * h;
  fill.y_min = 0.0;
  fill.y_max = surface();
  fill.density = density;
  fill.initial_state.void_ratio = void_ratio;
  fill_rectangle(particles, grid, Geometry::axisymmetric, fill);
  const double g = settings.gravity * gravity_multiplier;
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const double vertical = -density * g * (surface() - particles.position[p].y());
    particles.state[p].stress =
        diagonal6(earth_pressure * vertical, vertical, earth_pressure * vertical);
  }
  Settings s = settings;
  s.geometry = Geometry::axisymmetric;
  QuasiStaticSolver solver(std::move(grid), std::move(particles), {model}, s);
  RigidBody pile = RigidBody::pile(0.5 * diameter, surface(), kPi / 3.0);
  pile.set_friction(friction);
  solver.add_rigid_body(std::move(pile));
  return solver;
}

}  // namespace pilempm::mpm::quasi_static
