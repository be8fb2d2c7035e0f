// bodies.csv reports the contact force averaged over the time since the previous row, Σ F Δt / Σ
// Δt.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/mpm/solver.hpp"
#include "pilempm/simulation/body_force_means.hpp"

namespace pilempm {
namespace {

using namespace simulation;

TEST(MpmBodyForceMeans, MeanOfTheStepsSinceTheLastRow) {
  using mpm::Vec2;
  mpm::Grid grid(mpm::GridAxis::uniform(0.0, 1.0, 10), mpm::GridAxis::uniform(0.0, 1.0, 10));
  grid.set_boundary(mpm::Side::bottom, mpm::BoundaryCondition::fixed);
  mpm::Particles particles;
  mpm::RectangleFill fill;
  fill.x_max = 1.0;
  fill.y_max = 0.5;
  fill.density = 2000.0;
  mpm::fill_rectangle(particles, grid, mpm::Geometry::plane_strain, fill);
  mpm::SolverSettings settings;
  settings.gravity = 0.0;
  settings.threads = 1;
  mpm::Solver solver(std::move(grid), std::move(particles),
                     {std::make_shared<LinearElastic>(ElasticParameters{1.0e7, 0.3})}, settings);
  mpm::RigidBody plate = mpm::RigidBody::polygon({{0.2, 0.5}, {0.6, 0.5}, {0.6, 0.9}, {0.2, 0.9}});
  plate.set_velocity({0.0, -0.05});
  solver.add_rigid_body(plate);

  MpmBodyForceMeans means;
  double impulse = 0.0, tip_impulse = 0.0, elapsed = 0.0;
  for (int k = 0; k < 40; ++k) {
    const double dt = solver.step();
    means.add_step(solver, dt);
    impulse += solver.rigid_body_force(0).total.y() * dt;
    tip_impulse += solver.rigid_body_force(0).parts[0].y() * dt;
    elapsed += dt;
  }
  const std::vector<mpm::RigidBodyForce> mean = means.take(solver);
  ASSERT_EQ(mean.size(), 1u);
  EXPECT_GT(mean[0].total.y(), 0.0);
  EXPECT_NEAR(mean[0].total.y(), impulse / elapsed, 1e-12 * impulse / elapsed);
  EXPECT_NEAR(mean[0].parts[0].y(), tip_impulse / elapsed, 1e-12 * impulse / elapsed);
  // The single step's force differs from the mean (nodes come into contact step by step).
  EXPECT_NE(mean[0].total.y(), solver.rigid_body_force(0).total.y());
  // No time since the last take: the last step's force.
  const std::vector<mpm::RigidBodyForce> again = means.take(solver);
  EXPECT_EQ(again[0].total.y(), solver.rigid_body_force(0).total.y());
}

}  // namespace
}  // namespace pilempm
