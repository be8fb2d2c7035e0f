// Stress updates of hypoplasticity + intergranular strain on one core (issue: constitutive
// library, speed). A fixed mixed loading path from a 100 kPa isotropic state (e = 0.68, IGS
// fully mobilised along it), strain increments of 1e-6, 1e-5 and 1e-4, monotonic or with a
// reversal every 50 increments, at tolerance 1e-3. Each path covers 1 % strain and then starts
// again from the initial state. The counter `stress_error` is the largest relative difference of
// the final stress of a path from a run at tolerance 1e-7, i.e. the accuracy of what was timed.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <vector>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"

namespace {

using namespace pilempm;

MaterialState initial_state(const Hypoplastic& model) {
  MaterialState s;
  s.stress = -100e3 * identity6();
  s.void_ratio = 0.68;
  Hypoplastic::intergranular_strain(s) = -model.intergranular().R / kSqrt3 * identity6();
  return s;
}

// Compression with lateral bulging and some shear: a mixed, non-coaxial direction.
Vec6 path_direction() {
  Vec6 d;
  d << -1.0, 0.35, 0.25, 0.2, -0.1, 0.15;
  return d.normalized();
}

// Runs one path of `count` increments; returns the final state.
MaterialState run_path(const Hypoplastic& model, double size, long count, bool reversals,
                       long* substeps) {
  MaterialState s = initial_state(model);
  const Vec6 d = size * path_direction();
  for (long i = 0; i < count; ++i) {
    const bool reversed = reversals && (i / 50) % 2 == 1;
    const UpdateResult r = model.update(s, reversed ? Vec6(-0.4 * d) : d);
    if (substeps) *substeps += r.substeps;
  }
  return s;
}

void BM_HypoplasticIgsUpdate(benchmark::State& state) {
  const double size = std::pow(10.0, -static_cast<double>(state.range(0)));
  const bool reversals = state.range(1) != 0;
  const long count = std::max(100L, static_cast<long>(0.01 / size));
  IntegratorSettings settings;
  settings.tolerance = 1e-3;
  const Hypoplastic model(hypoplastic_set("original"), intergranular_strain_set("IGS3"), settings);
  IntegratorSettings tight = settings;
  tight.tolerance = 1e-7;
  const Hypoplastic reference(hypoplastic_set("original"), intergranular_strain_set("IGS3"), tight);

  long updates = 0, substeps = 0;
  for (auto _ : state) {
    MaterialState s = run_path(model, size, count, reversals, &substeps);
    benchmark::DoNotOptimize(s.stress.data());
    updates += count;
  }
  const MaterialState fast = run_path(model, size, count, reversals, nullptr);
  const MaterialState exact = run_path(reference, size, count, reversals, nullptr);
  state.counters["updates_per_s"] =
      benchmark::Counter(static_cast<double>(updates), benchmark::Counter::kIsRate);
  state.counters["substeps_per_update"] =
      static_cast<double>(substeps) / static_cast<double>(std::max(updates, 1L));
  state.counters["stress_error"] = (fast.stress - exact.stress).norm() / exact.stress.norm();
  state.counters["void_ratio_error"] = std::abs(fast.void_ratio - exact.void_ratio);
}

// Arguments: (-log10 of the increment size, reversals 0/1).
BENCHMARK(BM_HypoplasticIgsUpdate)
    ->ArgsProduct({{6, 5, 4}, {0, 1}})
    ->ArgNames({"log10_inc", "reversal"})
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
