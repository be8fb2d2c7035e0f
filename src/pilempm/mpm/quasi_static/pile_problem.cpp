#include "pilempm/mpm/quasi_static/pile_problem.hpp"

#include <cmath>
#include <memory>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/constitutive/mohr_coulomb/mohr_coulomb.hpp"

namespace pilempm::mpm::quasi_static {

Settings PileProblem::default_settings() {
  Settings s;
  s.step_limit = 0.1;
  return s;
}

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
  const auto* hypoplastic = dynamic_cast<const Hypoplastic*>(model.get());
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const double vertical = -density * g * (surface() - particles.position[p].y());
    particles.state[p].stress =
        diagonal6(earth_pressure * vertical, vertical, earth_pressure * vertical);
    if (hypoplastic != nullptr && hypoplastic->intergranular().enabled())
      Hypoplastic::intergranular_strain(particles.state[p]) =
          -hypoplastic->intergranular().R / kSqrt3 * identity6();
  }
  RigidBody pile =
      RigidBody::pile(0.5 * diameter, surface() - embedment_in_d * diameter, kPi / 3.0);
  pile.set_friction(friction);
  Settings s = settings;
  s.geometry = Geometry::axisymmetric;
  QuasiStaticSolver solver(std::move(grid), particles_outside(particles, {pile}), {model}, s);
  solver.add_rigid_body(std::move(pile));
  return solver;
}

ModelPtr pile_mohr_coulomb_sand() {
  MohrCoulombParameters mc;
  mc.young_modulus = 50.0e6;
  mc.poisson_ratio = 0.3;
  mc.cohesion = 1.0e3;
  mc.friction_angle_deg = 35.0;
  mc.dilatancy_angle_deg = 5.0;
  return std::make_shared<MohrCoulomb>(mc);
}

ModelPtr pile_hypoplastic_sand() {
  return std::make_shared<Hypoplastic>(hypoplastic_set("modified-medium-dense"),
                                       intergranular_strain_set("IGS3"));
}

}  // namespace pilempm::mpm::quasi_static
