// Explicit MPM steps (issue 4, speed): a 1.58 m x 1.58 m column of sand with about 100 000
// particles (158 x 158 cells of 1 cm, 2 x 2 particles per cell, cpGIMP, MUSL), rollers on the
// sides, fixed base, 40 g, local damping 0.1, from a K0 state (K0 = 0.5), in plane strain and in
// axisymmetry, with linear elasticity or hypoplasticity + intergranular strain ("original" set,
// IGS3, e0 = 0.68), on 1 and 2 threads. One iteration is one step; the counter
// particle_steps_per_s is what the targets are written in. The first 20 steps are run
// before timing (the transients of the first steps are not typical).
#include <benchmark/benchmark.h>

#include <memory>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/mpm/solver.hpp"

namespace {

using namespace pilempm;
using namespace pilempm::mpm;

constexpr double kVoidRatio = 0.68;
constexpr double kDensity = 2650.0 / (1.0 + kVoidRatio);  // dry density [kg/m^3]
constexpr double kGravityMultiplier = 40.0;
constexpr double kEarthPressure = 0.5;  // K0
constexpr double kCell = 0.01;          // [m]
constexpr int kCells = 160;
constexpr double kHeight = 158 * kCell;

Solver make_column(Geometry geometry, bool hypoplastic, int threads) {
  Grid grid(GridAxis::uniform(0.0, kCells * kCell, kCells),
            GridAxis::uniform(0.0, kCells * kCell, kCells));
  grid.set_boundary(Side::left, BoundaryCondition::roller);
  grid.set_boundary(Side::right, BoundaryCondition::roller);
  grid.set_boundary(Side::bottom, BoundaryCondition::fixed);

  ModelPtr model;
  double igs_size = 0.0;
  if (hypoplastic) {
    const auto hypo = std::make_shared<Hypoplastic>(hypoplastic_set("original"),
                                                    intergranular_strain_set("IGS3"));
    igs_size = hypo->intergranular().R;
    model = hypo;
  } else {
    model = std::make_shared<LinearElastic>(ElasticParameters{50e6, 0.3});
  }

  Particles particles;
  RectangleFill fill;
  fill.x_max = kHeight;
  fill.y_max = kHeight;
  fill.density = kDensity;
  fill.initial_state.void_ratio = kVoidRatio;
  fill_rectangle(particles, grid, geometry, fill);
  const double unit_weight = kDensity * 9.81 * kGravityMultiplier;
  for (std::size_t p = 0; p < particles.size(); ++p) {
    // K0 state under N g, with a small floor at the surface; IGS mobilised by the vertical load.
    const double vertical = -unit_weight * (kHeight - particles.position[p].y()) - 1e3;
    MaterialState& state = particles.state[p];
    state.stress = diagonal6(kEarthPressure * vertical, vertical, kEarthPressure * vertical);
    Hypoplastic::intergranular_strain(state) = diagonal6(0.0, -igs_size, 0.0);
  }

  SolverSettings settings;
  settings.geometry = geometry;
  settings.gravity_multiplier = kGravityMultiplier;
  settings.local_damping = 0.1;
  settings.flip_fraction = 0.99;
  settings.threads = threads;
  return Solver(std::move(grid), std::move(particles), {model}, settings);
}

// Arguments: geometry (0 plane strain, 1 axisymmetric), model (0 linear elastic, 1 hypoplastic
// + IGS), threads.
void BM_MpmStep(benchmark::State& state) {
  const auto geometry = state.range(0) == 0 ? Geometry::plane_strain : Geometry::axisymmetric;
  Solver solver = make_column(geometry, state.range(1) != 0, static_cast<int>(state.range(2)));
  for (int k = 0; k < 20; ++k) solver.step();
  for (auto _ : state) solver.step();
  const auto particles = static_cast<double>(solver.particles().size());
  state.counters["particles"] = particles;
  state.counters["particle_steps_per_s"] = benchmark::Counter(
      particles * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["bytes_per_particle"] = static_cast<double>(solver.bytes_per_particle());
}

BENCHMARK(BM_MpmStep)
    ->ArgsProduct({{0, 1}, {0, 1}, {1, 2}})
    ->ArgNames({"axisymmetric", "hypoplastic", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);

}  // namespace

BENCHMARK_MAIN();
