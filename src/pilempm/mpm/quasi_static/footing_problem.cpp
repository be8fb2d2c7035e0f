#include "pilempm/mpm/quasi_static/footing_problem.hpp"

#include <cmath>
#include <memory>

#include "pilempm/constitutive/mohr_coulomb/mohr_coulomb.hpp"

namespace pilempm::mpm::quasi_static {

Settings StripFootingProblem::default_settings() {
  Settings s;
  s.volumetric_averaging = true;
  s.step_limit = 0.05;
  s.contact.vertex_radius = 0.25;
  return s;
}

double StripFootingProblem::prandtl_pressure() const {
  return (2.0 + kPi) * cohesion;
}

QuasiStaticSolver StripFootingProblem::build() const {
  const double h = cell();
  const int columns = static_cast<int>(std::lround(soil_width / h));
  const int rows = static_cast<int>(std::lround(depth / h));
  // Four cells above the surface for the heave beside the footing.
  Grid grid(GridAxis::uniform(0.0, columns * h, columns),
            GridAxis::uniform(0.0, (rows + 4) * h, rows + 4));
  grid.set_boundary(Side::left, BoundaryCondition::roller);
  grid.set_boundary(Side::right, BoundaryCondition::roller);
  grid.set_boundary(Side::bottom, BoundaryCondition::fixed);
  Particles particles;
  RectangleFill fill;
  fill.x_max = columns * h;
  fill.y_max = rows * h;
  fill.density = density;
  fill_rectangle(particles, grid, Geometry::plane_strain, fill);
  MohrCoulombParameters soil;
  soil.young_modulus = young_modulus;
  soil.poisson_ratio = poisson_ratio;
  soil.cohesion = cohesion;
  soil.friction_angle_deg = 0.0;
  soil.dilatancy_angle_deg = 0.0;
  Settings s = settings;
  s.geometry = Geometry::plane_strain;
  QuasiStaticSolver solver(std::move(grid), std::move(particles),
                           {std::make_shared<MohrCoulomb>(soil)}, s);
  const double surface = rows * h;
  RigidBody footing = RigidBody::polygon({{-half_width, surface},
                                          {half_width, surface},
                                          {half_width, surface + depth},
                                          {-half_width, surface + depth}});
  footing.set_friction(friction);
  solver.add_rigid_body(std::move(footing));
  return solver;
}

}  // namespace pilempm::mpm::quasi_static
