// The explicit solver's surface contact (SolverSettings::contact = surface): the penalty law with
// Coulomb friction at the corners of the particles' domains against the exact surface of a rigid
// body (mpm/surface_contact.hpp, explicit/surface_contact.cpp). A block resting on a floor
// carries its weight with the predicted penetration; on an inclined plane it slides with the
// Coulomb acceleration and tangential force μ N, and sticks below the friction angle; a bounce
// does not create energy, also with a penalty stiff enough to set the time step.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <vector>

#include "../support/mpm_builders.hpp"
#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/mpm/solver.hpp"

namespace pilempm::mpm {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kG = 9.81, kDensity = 2000.0, kPoisson = 0.3, kYoung = 1.0e7;
constexpr double kFloor = 0.1, kTop = 0.3, kCell = 0.025;

// An elastic block [0.1, 0.5] x [0.1, 0.3] m (2 x 2 particles per 25 mm cell) on the rigid plane
// y = 0.1, at its geostatic stress under gravity g cos θ along −y, with g sin θ along +x as a load
// on each particle (the plane inclined by θ); contact = surface.
Solver block_on_plane(double angle, double friction, double damping) {
  Grid grid(GridAxis::uniform(0.0, 1.5, 60), GridAxis::uniform(0.0, 0.4, 16));
  RectangleFill fill = test_support::block_fill(0.1, 0.5, kFloor, kTop, kDensity);
  fill.initial_state.void_ratio = 0.7;
  Particles particles = test_support::particle_block(grid, Geometry::plane_strain, fill);
  test_support::set_geostatic_on_plane(particles, kDensity, kG, angle, kTop, kPoisson);
  SolverSettings settings;
  settings.gravity = kG * std::cos(angle);
  settings.local_damping = damping;
  settings.threads = 1;
  settings.contact = ContactScheme::surface;
  const auto model = std::make_shared<LinearElastic>(ElasticParameters{kYoung, kPoisson});
  Solver solver(std::move(grid), std::move(particles), {model}, settings);
  RigidBody plane = RigidBody::polygon({{-1.0, -1.0}, {3.0, -1.0}, {3.0, kFloor}, {-1.0, kFloor}});
  plane.set_friction(friction);
  solver.add_rigid_body(plane);
  return solver;
}

double total_mass(const Particles& p) {
  double mass = 0.0;
  for (double m : p.mass) mass += m;
  return mass;
}

Vec2 mean_velocity(const Particles& p) {
  Vec2 momentum = Vec2::Zero();
  for (std::size_t i = 0; i < p.size(); ++i) momentum += p.mass[i] * p.velocity[i];
  return momentum / total_mass(p);
}

// The mean and the largest depth of the particles' bottom corners below the floor [m].
Vec2 penetration(const Particles& p) {
  double sum = 0.0, deepest = 0.0;
  int count = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double depth = kFloor - (p.position[i].y() - p.half_size[i].y());
    if (depth <= 0.0) continue;
    sum += depth;
    ++count;
    deepest = std::max(deepest, depth);
  }
  return Vec2(count > 0 ? sum / count : 0.0, deepest);
}

// Time averages over [start, end] of the force of the soil on the body (total and per part).
struct MeanForce {
  Vec2 total = Vec2::Zero();
};

MeanForce mean_force(Solver& solver, double start, double end) {
  solver.run_until(start);
  MeanForce mean;
  while (solver.time() < end) {
    const double dt = solver.step();
    mean.total += dt * solver.rigid_body_force(0).total;
  }
  mean.total /= solver.time() - start;
  return mean;
}

TEST(ExplicitSurfaceContact, BlockRestingOnAFloorCarriesItsWeightWithThePredictedPenetration) {
  Solver solver = block_on_plane(0.0, 0.3, 0.3);
  const double weight = total_mass(solver.particles()) * kG;
  const MeanForce mean = mean_force(solver, 0.25, 0.3);
  const RigidBodyForce& last = solver.rigid_body_force(0);
  // At rest a bottom corner carries on average ρ g H l (l = 6.25 mm the half particle size) on a
  // spring k_n = β M (square particles): the mean penetration ρ g H l / (β M), M the constrained
  // modulus (the corners at the block's edges go deeper).
  const double modulus = kYoung * (1.0 - kPoisson) / ((1.0 + kPoisson) * (1.0 - 2.0 * kPoisson));
  const double expected = kDensity * kG * (kTop - kFloor) * 0.25 * kCell /
                          (SolverSettings{}.surface_contact.penalty_factor * modulus);
  const Vec2 depths = penetration(solver.particles());
  const double depth = depths.x();
  std::printf(
      "block on floor, surface contact: mean normal force / weight %.6f (last step %.6f), "
      "tangential %.2e; mean penetration %.3e m (predicted %.3e m, %.2e cells), deepest %.3e m, "
      "|v| %.2e m/s\n",
      -mean.total.y() / weight, -last.total.y() / weight, mean.total.x() / weight, depth, expected,
      depth / kCell, depths.y(), mean_velocity(solver.particles()).norm());
  EXPECT_NEAR(-mean.total.y() / weight, 1.0, 2e-3);
  EXPECT_NEAR(-last.total.y() / weight, 1.0, 5e-3);
  EXPECT_LT(std::abs(mean.total.x()) / weight, 1e-3);
  EXPECT_NEAR(depth / expected, 1.0, 0.02);
  EXPECT_LT(depths.y(), 1e-3 * kCell);
  // The floor's only part carries it all.
  ASSERT_EQ(last.parts.size(), 4u);
  Vec2 sum = Vec2::Zero();
  for (const Vec2& part : last.parts) sum += part;
  EXPECT_NEAR((sum - last.total).norm(), 0.0, 1e-9 * weight);
  EXPECT_NEAR(last.parts[2].y(), last.total.y(), 1e-9 * weight);  // edge 2: the top y = 0.1
}

TEST(ExplicitSurfaceContact, BlockSlidesDownAnInclinedPlaneWithTangentialForceMuN) {
  const double angle = 30.0 * kPi / 180.0, friction = 0.3;
  Solver solver = block_on_plane(angle, friction, 0.0);
  solver.run_until(0.05);
  const double v0 = mean_velocity(solver.particles()).x();
  const MeanForce mean = mean_force(solver, 0.05, 0.2);
  const double v1 = mean_velocity(solver.particles()).x();
  const double acceleration = (v1 - v0) / (solver.time() - 0.05);
  const double expected = kG * (std::sin(angle) - friction * std::cos(angle));
  const double ratio = -mean.total.x() / -mean.total.y();  // the soil's drag on the plane: +x
  std::printf(
      "inclined plane 30 deg, mu 0.3, surface contact: a = %.5f m/s^2 (expected %.5f), "
      "mean tangential / normal force %.5f\n",
      acceleration, expected, -ratio);
  EXPECT_NEAR(acceleration / expected, 1.0, 0.02);
  // The plane drags the block back (−x on the soil): the body receives +μ N along x.
  EXPECT_NEAR(-ratio, friction, 0.01 * friction);
}

TEST(ExplicitSurfaceContact, BlockSticksOnAnInclinedPlaneBelowTheFrictionAngle) {
  const double angle = 10.0 * kPi / 180.0, friction = 0.3;
  Solver solver = block_on_plane(angle, friction, 0.0);
  const double weight = total_mass(solver.particles()) * kG;
  const MeanForce mean = mean_force(solver, 0.05, 0.2);
  const double speed = std::abs(mean_velocity(solver.particles()).x());
  const double free_speed = kG * std::sin(angle) * 0.2;
  std::printf(
      "inclined plane 10 deg, mu 0.3, surface contact: |v| = %.3e m/s (free slide %.3f m/s), "
      "mean tangential force / (W sin θ) %.5f\n",
      speed, free_speed, mean.total.x() / (weight * std::sin(angle)));
  EXPECT_LT(speed, 1e-2 * free_speed);
  // Stick: the plane carries the whole tangential load, below μ N.
  EXPECT_NEAR(mean.total.x() / (weight * std::sin(angle)), 1.0, 0.03);
}

// A restart from the run state (the corners' friction histories, the springs' frequency bound and
// the fixed penalty modulus) continues the sliding block to the bit, and the stored modulus is
// the block's constrained modulus M = E (1 − ν) / ((1 + ν)(1 − 2ν)).
TEST(ExplicitSurfaceContact, ARestartFromTheRunStateContinuesToTheBit) {
  const double angle = 30.0 * kPi / 180.0, friction = 0.3;
  Solver straight = block_on_plane(angle, friction, 0.0);
  straight.run_until(0.03);
  const SolverRunState state = straight.run_state();
  const Particles particles = straight.particles();
  const std::vector<double>* modulus = nullptr;
  for (const auto& [key, values] : state.scheme_arrays)
    if (key == "surface_contact_modulus_Pa") modulus = &values;
  ASSERT_NE(modulus, nullptr);
  ASSERT_EQ(modulus->size(), 1u);
  const double expected = kYoung * (1.0 - kPoisson) / ((1.0 + kPoisson) * (1.0 - 2.0 * kPoisson));
  EXPECT_NEAR(modulus->front() / expected, 1.0, 1e-12);

  Solver restarted = block_on_plane(angle, friction, 0.0);
  restarted.particles() = particles;
  restarted.restore_run_state(state);
  straight.run_until(0.06);
  restarted.run_until(0.06);
  ASSERT_EQ(restarted.steps(), straight.steps());
  for (std::size_t p = 0; p < particles.size(); ++p) {
    EXPECT_EQ(restarted.particles().position[p], straight.particles().position[p]) << p;
    EXPECT_EQ(restarted.particles().velocity[p], straight.particles().velocity[p]) << p;
  }
  EXPECT_EQ(restarted.rigid_body_force(0).total, straight.rigid_body_force(0).total);
}

// A free elastic block thrown at the floor without gravity or damping (μ = 0.3): it bounces, and
// after it has left the floor neither its kinetic energy nor its kinetic plus strain energy is
// above the kinetic energy it arrived with; with β = 200 the penalty springs set the time step.
void bounce(double penalty_factor) {
  Grid grid(GridAxis::uniform(0.0, 1.0, 40), GridAxis::uniform(0.0, 0.5, 20));
  RectangleFill fill = test_support::block_fill(0.3, 0.5, 0.15, 0.25, kDensity);
  fill.initial_state.void_ratio = 0.7;
  fill.initial_velocity = Vec2(0.3, -1.0);
  Particles particles = test_support::particle_block(grid, Geometry::plane_strain, fill);
  SolverSettings settings;
  settings.gravity = 0.0;
  settings.threads = 1;
  settings.flip_fraction = 1.0;
  settings.contact = ContactScheme::surface;
  settings.surface_contact.penalty_factor = penalty_factor;
  const auto model = std::make_shared<LinearElastic>(ElasticParameters{kYoung, kPoisson});
  Solver solver(std::move(grid), std::move(particles), {model}, settings);
  RigidBody floor = RigidBody::polygon({{-1.0, -1.0}, {2.0, -1.0}, {2.0, kFloor}, {-1.0, kFloor}});
  floor.set_friction(0.3);
  solver.add_rigid_body(floor);
  const double before = solver.energies().kinetic;
  const double cfl = solver.next_time_step();
  double smallest_step = cfl;
  bool touched = false;
  while (solver.time() < 0.1) {  // arrival at 0.05 s, contact for about 2 H / c = 3 ms
    smallest_step = std::min(smallest_step, solver.step());
    touched = touched || solver.rigid_body_force(0).total.norm() > 0.0;
  }
  const Energies& e = solver.energies();
  const double rebound = mean_velocity(solver.particles()).y();
  std::printf(
      "bounce, beta %g: kinetic after / before %.4f, (kinetic + strain) / before %.4f, "
      "rebound v_y %.3f m/s, smallest step / CFL step %.3f\n",
      penalty_factor, e.kinetic / before, (e.kinetic + e.internal) / before, rebound,
      smallest_step / cfl);
  ASSERT_TRUE(touched);
  EXPECT_GT(rebound, 0.3);  // it bounced and left
  EXPECT_EQ(solver.rigid_body_force(0).total.norm(), 0.0);
  EXPECT_LE(e.kinetic, before);
  EXPECT_LE(e.kinetic + e.internal, before * (1.0 + 1e-3));
  if (penalty_factor > 100.0) {
    EXPECT_LT(smallest_step, 0.5 * cfl);  // the springs set the step
  }
}

TEST(ExplicitSurfaceContact, ABounceCreatesNoEnergy) {
  bounce(2.0);
}

TEST(ExplicitSurfaceContact, ABounceOnStiffPenaltySpringsCreatesNoEnergy) {
  bounce(200.0);
}

}  // namespace
}  // namespace pilempm::mpm
