// Threads: a run is bitwise repeatable for a given thread count (static split of the particles,
// per-thread nodal sums added in thread order), and runs with different thread counts agree to
// round-off (the nodal sums are added in a different order).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include "../support/mpm_builders.hpp"
#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/mpm/solver.hpp"

namespace pilempm::mpm {
namespace {

// A block of soil dropped onto a fixed floor inside roller walls, with some random velocity,
// gravity, local damping and a graded grid: every part of the step does something.
Particles run(int threads, Geometry geometry, UpdateScheme scheme, long steps) {
  Grid grid(GridAxis::graded(0.0, 1.0, 0.0, 0.4, 0.02, 1.2), GridAxis::uniform(0.0, 0.8, 40));
  test_support::set_walls_and_fixed_base(grid);
  RectangleFill fill = test_support::block_fill(0.0, 0.6, 0.1, 0.5, 1800.0);
  fill.initial_state.stress = -5e3 * identity6();
  Particles particles = test_support::particle_block(grid, geometry, fill);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> noise(-0.05, 0.05);
  for (Vec2& v : particles.velocity) v = Vec2(noise(rng), -0.5 + noise(rng));
  SolverSettings settings;
  settings.geometry = geometry;
  settings.scheme = scheme;
  settings.flip_fraction = 0.98;
  settings.local_damping = 0.05;
  settings.gravity_multiplier = 10.0;
  settings.threads = threads;
  Solver solver(std::move(grid), std::move(particles),
                {std::make_shared<LinearElastic>(ElasticParameters{5e6, 0.3})}, settings);
  for (long k = 0; k < steps; ++k) solver.step();
  return solver.particles();
}

struct Difference {
  double position = 0.0;  // max |Δx| [m]
  double velocity = 0.0;  // max |Δv| / max |v|
  double stress = 0.0;    // max |Δσ| / max |σ|
};

Difference compare(const Particles& a, const Particles& b) {
  Difference d;
  double max_velocity = 0.0, max_stress = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    d.position = std::max(d.position, (a.position[i] - b.position[i]).norm());
    d.velocity = std::max(d.velocity, (a.velocity[i] - b.velocity[i]).norm());
    d.stress = std::max(d.stress, (a.state[i].stress - b.state[i].stress).cwiseAbs().maxCoeff());
    max_velocity = std::max(max_velocity, a.velocity[i].norm());
    max_stress = std::max(max_stress, a.state[i].stress.cwiseAbs().maxCoeff());
  }
  d.velocity /= max_velocity;
  d.stress /= max_stress;
  return d;
}

void check_threads(Geometry geometry, UpdateScheme scheme, const char* label) {
  const long steps = 150;
  const Particles one = run(1, geometry, scheme, steps);
  const Particles two = run(2, geometry, scheme, steps);
  const Particles two_again = run(2, geometry, scheme, steps);
  const Particles three = run(3, geometry, scheme, steps);
  const Difference repeat = compare(two, two_again);
  EXPECT_EQ(repeat.position, 0.0) << label;
  EXPECT_EQ(repeat.velocity, 0.0) << label;
  EXPECT_EQ(repeat.stress, 0.0) << label;
  for (const Particles* other : {&two, &three}) {
    const Difference d = compare(one, *other);
    std::printf(
        "[ threads %s ] %zu particles, %ld steps, 1 vs %d threads: max position "
        "difference %.2e m, velocity %.2e and stress %.2e relative to their largest\n",
        label, one.size(), steps, other == &two ? 2 : 3, d.position, d.velocity, d.stress);
    EXPECT_LT(d.position, 1e-12) << label;
    EXPECT_LT(d.velocity, 1e-9) << label;
    EXPECT_LT(d.stress, 1e-9) << label;
  }
}

TEST(Threads, PlaneStrainMuslIsRepeatableAndIndependentOfThreadCount) {
  check_threads(Geometry::plane_strain, UpdateScheme::musl, "plane strain MUSL");
}

TEST(Threads, AxisymmetricUslIsRepeatableAndIndependentOfThreadCount) {
  check_threads(Geometry::axisymmetric, UpdateScheme::usl, "axisymmetric USL");
}

}  // namespace
}  // namespace pilempm::mpm
