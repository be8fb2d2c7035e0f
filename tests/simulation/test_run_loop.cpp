// The run loop: it tells its observers every step, record and snapshot at the times the phases
// ask for, and an interval it could not step through (a typed case is not range-checked by a
// reader) is an error naming the phase and the key, not a loop that never ends.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <future>
#include <string>
#include <vector>

#include "pilempm/core/error.hpp"
#include "pilempm/io/mpm_case.hpp"
#include "pilempm/simulation/explicit_scheme.hpp"
#include "pilempm/simulation/run_loop.hpp"

namespace pilempm {
namespace {

using namespace simulation;

// An elastic column, stress free, settling under gravity: 0.02 s, records every 0.005 s,
// snapshots every 0.01 s.
const char* const kColumn = R"(title = "column"
[geometry]
kind = "plane-strain"
[grid.x]
spacing = "uniform"
min_m = 0.0
max_m = 0.4
cells = 2
[grid.y]
spacing = "uniform"
min_m = 0.0
max_m = 1.2
cells = 6
[boundaries]
left = "roller"
right = "roller"
bottom = "fixed"
[solver]
threads = 1
[[material]]
name = "soil"
model = "linear-elastic"
young_modulus_MPa = 10.0
poisson_ratio = 0.3
[[region]]
x_min_m = 0.0
x_max_m = 0.4
y_min_m = 0.0
y_max_m = 1.0
particles_per_cell = 2
density_kg_per_m3 = 2000.0
material = "soil"
initial_stress = "zero"
[[phase]]
name = "settle"
duration_s = 0.02
output_interval_s = 0.01
energy_interval_s = 0.005
)";

// Counts what the loop tells and checks that time never goes back.
struct CountingObserver final : RunObserver {
  int steps = 0, records = 0, snapshots = 0, phase_ends = 0;
  double last_time = -1.0;
  std::vector<double> record_times;
  void after_step(const Scheme& scheme, const MpmPhase&, double dt) override {
    ++steps;
    EXPECT_GT(dt, 0.0);
    EXPECT_GT(scheme.time(), last_time);
    last_time = scheme.time();
  }
  void record(const Scheme& scheme, const MpmPhase&) override {
    ++records;
    record_times.push_back(scheme.time());
  }
  void snapshot(const Scheme&, const MpmPhase&) override { ++snapshots; }
  void phase_end(const Scheme&, const MpmPhase&) override { ++phase_ends; }
};

TEST(RunLoop, RecordsAndSnapshotsLandExactlyOnTheirTimes) {
  const MpmCase c = read_mpm_case_text(kColumn, "column.toml");
  ExplicitScheme scheme(c);
  CountingObserver counter;
  const std::vector<MpmPhaseEnd> ends = run_phases(c, scheme, 0, {&counter});
  ASSERT_EQ(ends.size(), 1u);
  EXPECT_EQ(ends[0].reason, "duration_s");
  EXPECT_DOUBLE_EQ(ends[0].time, 0.02);
  // t = 0 and every 0.005 s to 0.02 s; snapshots at 0, 0.01 and 0.02 s.
  ASSERT_EQ(counter.records, 5);
  for (int k = 0; k < 5; ++k) EXPECT_NEAR(counter.record_times[k], 0.005 * k, 1e-15);
  EXPECT_EQ(counter.snapshots, 3);
  EXPECT_EQ(counter.phase_ends, 1);
  EXPECT_EQ(ends[0].steps, counter.steps);
}

// Runs `run` on a thread; a run that has not ended after a minute ends the test program with a
// failure instead of hanging the suite.
void expect_error_within_a_minute(const MpmCase& c, const std::string& key) {
  auto run = std::async(std::launch::async, [&c] {
    ExplicitScheme scheme(c);
    try {
      run_phases(c, scheme, 0, {});
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  });
  if (run.wait_for(std::chrono::seconds(60)) != std::future_status::ready) {
    ADD_FAILURE() << "the run loop did not end with " << key << " = 1e-300";
    std::_Exit(EXIT_FAILURE);
  }
  const std::string message = run.get();
  EXPECT_NE(message.find("phase \"settle\""), std::string::npos) << message;
  EXPECT_NE(message.find(key + " = 1e-300"), std::string::npos) << message;
}

TEST(RunLoop, AnEnergyIntervalFarBelowTheTimeStepIsAnErrorNotAHang) {
  MpmCase c = read_mpm_case_text(kColumn, "column.toml");
  c.phases[0].energy_interval = 1e-300;
  expect_error_within_a_minute(c, "energy_interval_s");
}

TEST(RunLoop, AnOutputIntervalFarBelowTheTimeStepIsAnErrorNotAHang) {
  MpmCase c = read_mpm_case_text(kColumn, "column.toml");
  c.phases[0].output_interval = 1e-300;
  expect_error_within_a_minute(c, "output_interval_s");
}

}  // namespace
}  // namespace pilempm
