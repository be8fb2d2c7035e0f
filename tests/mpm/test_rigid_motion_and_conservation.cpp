// Kinematic checks of the solver: a free block in uniform translation moves exactly and stays
// stress-free; linear momentum is conserved to round-off with internal forces and no external
// ones; a rigidly spinning block keeps its angular momentum (FLIP) up to a discretisation error
// that vanishes with mesh refinement.
// Also: the errors the solver raises, and the axis condition in axisymmetry.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>

#include "../support/mpm_builders.hpp"
#include "../support/refusing_model.hpp"
#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/mpm/solver.hpp"

namespace pilempm::mpm {
namespace {

constexpr double kDensity = 2000.0;
constexpr double kYoung = 10.0e6;

ModelPtr elastic() {
  return std::make_shared<LinearElastic>(ElasticParameters{kYoung, 0.25});
}

// A 2 m x 2 m grid of 20 x 20 cells with a 0.5 m x 0.4 m block of 2 x 2 particles per cell.
Solver free_block(const SolverSettings& settings, const Vec2& velocity, int cells = 20) {
  Grid grid(GridAxis::uniform(0.0, 2.0, cells), GridAxis::uniform(0.0, 2.0, cells));
  RectangleFill fill = test_support::block_fill(0.6, 1.1, 0.8, 1.2, kDensity);
  fill.initial_velocity = velocity;
  Particles particles = test_support::particle_block(grid, settings.geometry, fill);
  return Solver(std::move(grid), std::move(particles), {elastic()}, settings);
}

Vec2 total_momentum(const Particles& p) {
  Vec2 sum = Vec2::Zero();
  for (std::size_t i = 0; i < p.size(); ++i) sum += p.mass[i] * p.velocity[i];
  return sum;
}

struct Variant {
  UpdateScheme scheme;
  ShapeFunction shape;
  double flip;
  const char* label;
};

const Variant kVariants[] = {
    {UpdateScheme::musl, ShapeFunction::cpgimp, 1.0, "MUSL cpGIMP FLIP"},
    {UpdateScheme::musl, ShapeFunction::ugimp, 0.0, "MUSL uGIMP PIC"},
    {UpdateScheme::usl, ShapeFunction::cpgimp, 0.95, "USL cpGIMP blend"},
    {UpdateScheme::musl, ShapeFunction::linear, 1.0, "MUSL linear FLIP"},
    {UpdateScheme::usl, ShapeFunction::ugimp, 1.0, "USL uGIMP FLIP"},
};

// A variant's settings without gravity, on one thread.
SolverSettings free_settings(const Variant& v) {
  SolverSettings settings;
  settings.scheme = v.scheme;
  settings.shape_function = v.shape;
  settings.flip_fraction = v.flip;
  settings.gravity = 0.0;
  settings.threads = 1;
  return settings;
}

TEST(RigidMotion, UniformTranslationIsExactAndStressFree) {
  const Vec2 velocity(1.5, -0.7);
  for (const Variant& v : kVariants) {
    Solver solver = free_block(free_settings(v), velocity);
    const Particles start = solver.particles();
    // 0.25 m of travel: two and a half cells, so particles cross cell boundaries.
    solver.run_until(0.25 / velocity.norm());
    const Particles& p = solver.particles();
    double position_error = 0.0, velocity_error = 0.0, stress = 0.0, volume_change = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Vec2 exact = start.position[i] + solver.time() * velocity;
      position_error = std::max(position_error, (p.position[i] - exact).norm());
      velocity_error = std::max(velocity_error, (p.velocity[i] - velocity).norm());
      stress = std::max(stress, p.state[i].stress.cwiseAbs().maxCoeff());
      volume_change = std::max(volume_change, std::abs(p.volume[i] / start.volume[i] - 1.0));
    }
    std::printf(
        "[ translation %s ] %ld steps: position error %.2e m, velocity error %.2e m/s, "
        "largest stress %.2e Pa, volume change %.2e\n",
        v.label, solver.steps(), position_error, velocity_error, stress, volume_change);
    EXPECT_LT(position_error, 1e-12) << v.label;
    EXPECT_LT(velocity_error, 1e-12) << v.label;
    EXPECT_LT(stress, 1e-4) << v.label;  // E = 10 MPa: a strain of 1e-11
    EXPECT_LT(volume_change, 1e-11) << v.label;
    EXPECT_GT(solver.energies().kinetic, 0.0);
    EXPECT_NEAR(solver.energies().internal, 0.0, 1e-12);
  }
}

TEST(Conservation, LinearMomentumIsConservedWithInternalForces) {
  // Random particle velocities deform the block; with no gravity, no damping and no boundary in
  // reach, the nodal internal forces sum to zero and the total momentum cannot change.
  for (const Variant& v : kVariants) {
    Solver solver = free_block(free_settings(v), Vec2::Zero());
    // A drift, a smooth squeeze and random noise.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> noise(-0.2, 0.2);
    Particles& p = solver.particles();
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Vec2 r = p.position[i] - Vec2(0.85, 1.0);
      p.velocity[i] =
          Vec2(0.3, -0.1) + Vec2(-2.0 * r.x(), 1.5 * r.y()) + Vec2(noise(rng), noise(rng));
    }
    const Vec2 initial = total_momentum(solver.particles());
    double scale = 0.0;  // Σ m |v|, the size of the momenta that cancel
    for (std::size_t i = 0; i < solver.particles().size(); ++i)
      scale += solver.particles().mass[i] * solver.particles().velocity[i].norm();
    double largest_stress = 0.0;  // over the run
    for (int k = 0; k < 300; ++k) {
      solver.step();
      for (const MaterialState& s : solver.particles().state)
        largest_stress = std::max(largest_stress, s.stress.cwiseAbs().maxCoeff());
    }
    const double change = (total_momentum(solver.particles()) - initial).norm() / scale;
    std::printf("[ momentum %s ] relative change after 300 steps %.2e (stresses up to %.2e Pa)\n",
                v.label, change, largest_stress);
    EXPECT_LT(change, 1e-13) << v.label;
    EXPECT_GT(largest_stress, 1e3) << v.label;  // the internal forces were not trivial
  }
}

// Rigid rotation is not exact in MPM: a node at the block's edge gets the mass-weighted mean of
// the particle velocities, ω × (the particles' mean position), not ω × its own position, so the
// edge cells see a spurious strain rate of order ω and part of the kinetic energy goes into
// strain energy, while FLIP does not conserve angular momentum exactly. Both errors shrink as
// the cells get smaller relative to the block (APIC-type transfers would remove them).
double spin_block(int cells) {
  SolverSettings settings;
  settings.flip_fraction = 1.0;  // PIC would dissipate the rotation
  settings.gravity = 0.0;
  settings.threads = 1;
  Solver solver = free_block(settings, Vec2::Zero(), cells);
  const Vec2 centre(0.85, 1.0);
  const double omega = 2.0;  // rad/s
  Particles& p = solver.particles();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2 r = p.position[i] - centre;
    p.velocity[i] = omega * Vec2(-r.y(), r.x());
  }
  auto angular_momentum = [&] {
    double sum = 0.0;
    const Particles& q = solver.particles();
    for (std::size_t i = 0; i < q.size(); ++i) {
      const Vec2 r = q.position[i] - centre;
      sum += q.mass[i] * (r.x() * q.velocity[i].y() - r.y() * q.velocity[i].x());
    }
    return sum;
  };
  const double initial = angular_momentum();
  double initial_kinetic = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    initial_kinetic += 0.5 * p.mass[i] * p.velocity[i].squaredNorm();
  double mass = 0.0;
  for (double m : p.mass) mass += m;
  solver.run_until(0.25 * kPi / omega);  // an eighth of a turn
  const double change = angular_momentum() / initial - 1.0;
  double largest_stress = 0.0;
  for (const MaterialState& s : solver.particles().state)
    largest_stress = std::max(largest_stress, s.stress.cwiseAbs().maxCoeff());
  // Scale of real (centrifugal) stress: ρ ω² R² with R the half-diagonal, 0.32 m.
  const double centrifugal = kDensity * omega * omega * 0.32 * 0.32;
  std::printf(
      "[ spin, %2d cells ] %ld steps: angular momentum change %+.2e, strain energy %.2e "
      "of the initial kinetic energy, linear momentum %.1e kg m/s, largest stress %.2e Pa "
      "(ρω²R² = %.2e Pa)\n",
      cells, solver.steps(), change, solver.energies().internal / initial_kinetic,
      total_momentum(solver.particles()).norm(), largest_stress, centrifugal);
  EXPECT_LT(total_momentum(solver.particles()).norm(), 1e-12 * mass * omega * 0.32);
  return std::abs(change);
}

TEST(RigidMotion, SpinningBlockKeepsAngularMomentumAsTheMeshIsRefined) {
  const double coarse = spin_block(20);  // 5 x 4 cells across the block
  const double medium = spin_block(40);
  const double fine = spin_block(80);
  EXPECT_LT(medium, 0.5 * coarse);
  EXPECT_LT(fine, 0.5 * medium);
  EXPECT_LT(fine, 0.03);
}

// A uniform load on every particle of a free block: the block accelerates as a whole with
// a = ΣF / Σm, and the work of the loads is the kinetic energy.
TEST(RigidMotion, UniformParticleLoadAcceleratesTheBlockAsAWhole) {
  SolverSettings settings;
  settings.gravity = 0.0;
  settings.threads = 1;
  settings.fixed_time_step = 1e-4;
  Solver solver = free_block(settings, Vec2::Zero());
  Particles& p = solver.particles();
  double mass = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.external_force[i] = Vec2(3.0, -1.0) * p.mass[i];  // 3 m/s^2 along x, -1 m/s^2 along y
    mass += p.mass[i];
  }
  solver.run_until(0.2);
  const Vec2 expected(0.6, -0.2);  // a t
  double velocity_error = 0.0;
  for (const Vec2& v : solver.particles().velocity)
    velocity_error = std::max(velocity_error, (v - expected).norm());
  const double kinetic = 0.5 * mass * expected.squaredNorm();
  std::printf("[ particle load ] velocity error %.2e m/s, work %.6f J, kinetic %.6f J\n",
              velocity_error, solver.energies().external_work, solver.energies().kinetic);
  EXPECT_LT(velocity_error, 1e-12);
  EXPECT_NEAR(solver.energies().kinetic, kinetic, 1e-10 * kinetic);
  // Δx = v^{n+1} Δt (symplectic Euler): the work exceeds ½ m v² by ½ m a² t Δt.
  EXPECT_NEAR(solver.energies().external_work, kinetic, 1e-3 * kinetic);
}

TEST(SolverErrors, AFailedStressUpdateNamesParticleStepAndTime) {
  Grid grid(GridAxis::uniform(0.0, 1.0, 4), GridAxis::uniform(0.0, 1.0, 4));
  grid.set_boundary(Side::bottom, BoundaryCondition::fixed);
  Particles particles = test_support::particle_block(
      grid, Geometry::plane_strain, test_support::block_fill(0.0, 1.0, 0.0, 0.5, kDensity));
  particles.material[9] = 1;
  particles.material[13] = 1;
  SolverSettings settings;
  settings.threads = 2;
  Solver solver(std::move(grid), std::move(particles),
                {elastic(), std::make_shared<pilempm::test_support::RefusingModel>(
                                "refusing", "refused on purpose", kYoung)},
                settings);
  try {
    solver.step();
    FAIL() << "no error";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("particle 9 "), std::string::npos) << message;
    EXPECT_NE(message.find("step 1 "), std::string::npos) << message;
    EXPECT_NE(message.find("time 0 s"), std::string::npos) << message;
    EXPECT_NE(message.find("refusing"), std::string::npos) << message;
    EXPECT_NE(message.find("refused on purpose"), std::string::npos) << message;
  }
}

TEST(SolverErrors, BadInputIsRejected) {
  SolverSettings settings;
  settings.flip_fraction = 1.5;
  EXPECT_THROW(settings.validate(), InvalidValue);
  settings = {};
  settings.local_damping = 1.0;
  EXPECT_THROW(settings.validate(), InvalidValue);
  settings = {};
  settings.courant_number = 0.0;
  EXPECT_THROW(settings.validate(), InvalidValue);

  const Grid grid(GridAxis::uniform(0.0, 1.0, 4), GridAxis::uniform(0.0, 1.0, 4));
  Particles particles;
  ParticleInit particle;
  particle.position = Vec2(0.5, 0.5);
  particle.mass = 1.0;
  particle.volume = 1e-3;
  particle.material = 2;  // only one material given
  particles.add(particle);
  EXPECT_THROW(Solver(grid, particles, {elastic()}), InvalidValue);
  particles.material[0] = 0;
  particles.position[0] = Vec2(1.5, 0.5);  // outside the grid
  EXPECT_THROW(Solver(grid, particles, {elastic()}), InvalidValue);
  particles.position[0] = Vec2(0.5, 0.5);
  EXPECT_NO_THROW(Solver(grid, particles, {elastic()}));
  EXPECT_THROW(Solver(grid, particles, {nullptr}), InvalidValue);
}

TEST(SolverErrors, AParticleLeavingTheGridStopsTheRun) {
  SolverSettings settings;
  settings.gravity = 0.0;
  settings.threads = 1;
  Solver solver = free_block(settings, Vec2(40.0, 0.0));  // 0.9 m to the edge
  EXPECT_THROW(solver.run_until(0.1), Error);
}

TEST(Axisymmetry, RadialVelocityIsZeroOnTheAxis) {
  // A disc of material next to the axis moving inwards, with a free left side: the nodes on r = 0
  // get no radial velocity, and the material stops there instead of crossing the axis.
  Grid grid(GridAxis::uniform(0.0, 1.0, 10), GridAxis::uniform(0.0, 1.0, 10));
  RectangleFill fill = test_support::block_fill(0.0, 0.3, 0.4, 0.6, kDensity);
  fill.initial_velocity = Vec2(-0.2, 0.0);
  SolverSettings settings;
  settings.geometry = Geometry::axisymmetric;
  settings.gravity = 0.0;
  settings.threads = 1;
  Particles particles = test_support::particle_block(grid, settings.geometry, fill);
  Solver solver(std::move(grid), std::move(particles), {elastic()}, settings);
  for (int k = 0; k < 50; ++k) {
    solver.step();
    const Grid& g = solver.grid();
    for (int j = 0; j < g.ny(); ++j) ASSERT_EQ(g.nodes().velocity_x[g.node_index(0, j)], 0.0);
  }
  for (const Vec2& x : solver.particles().position) EXPECT_GT(x.x(), 0.0);
  // Converging radial flow compresses the hoop direction: σ_θθ < 0 near the axis.
  EXPECT_LT(solver.particles().state[0].stress[k33], 0.0);
}

}  // namespace
}  // namespace pilempm::mpm
