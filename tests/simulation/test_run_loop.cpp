// The run loop: it tells its observers every step, record and snapshot at the times the phases
// ask for, and an interval it could not step through (a typed case is not range-checked by a
// reader) is an error naming the phase and the key, not a loop that never ends.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <future>
#include <string>
#include <vector>

#include "../support/case_builders.hpp"
#include "../support/material_builders.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/simulation/explicit_scheme.hpp"
#include "pilempm/simulation/run_loop.hpp"

namespace pilempm {
namespace {

using namespace simulation;

// An elastic column, stress free, settling under gravity: 0.02 s, records every 0.005 s,
// snapshots every 0.01 s (0.4 m wide, 1 m high, on a grid of 0.2 m cells, rollers on the sides,
// a fixed base, one thread).
MpmCase column_case() {
  MpmCase c = test_support::grid_case("column", mpm::Geometry::plane_strain,
                                      test_support::uniform_axis(0.0, 0.4, 2),
                                      test_support::uniform_axis(0.0, 1.2, 6));
  c.boundaries[static_cast<std::size_t>(mpm::Side::left)] = mpm::BoundaryCondition::roller;
  c.boundaries[static_cast<std::size_t>(mpm::Side::right)] = mpm::BoundaryCondition::roller;
  c.boundaries[static_cast<std::size_t>(mpm::Side::bottom)] = mpm::BoundaryCondition::fixed;
  c.solver.threads = 1;
  mpm::RectangleFill fill;
  fill.x_max = 0.4;
  fill.y_max = 1.0;
  fill.density = 2000.0;
  test_support::add_region(c, test_support::linear_elastic_material("soil", 10.0e6, 0.3), fill);
  test_support::add_phase(c, "settle", 0.02, 0.01, 0.005);
  return c;
}

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
  const MpmCase c = column_case();
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

// A scheme that never reports a step as ending on its target, as the quasi-static scheme does for
// a step in which a force rule was bisected (its last re-solve may end on the target itself):
// the loop takes a step that ends at the target time as at the target. MPM-2 on the quasi-static
// analysis stopped so in its relaxation ("the next output time ... is not after the time").
class NeverAtTarget final : public Scheme {
 public:
  explicit NeverAtTarget(Scheme& inner) : inner_(inner) {}
  std::string begin_phase(std::size_t index) override { return inner_.begin_phase(index); }
  Advance advance(double target) override {
    Advance advance = inner_.advance(target);
    advance.at_target = false;
    return advance;
  }
  PhaseProgress phase_progress() const override { return inner_.phase_progress(); }
  double phase_end_time() const override { return inner_.phase_end_time(); }
  double time() const override { return inner_.time(); }
  long steps() const override { return inner_.steps(); }
  double step_length() override { return inner_.step_length(); }
  bool inertial() const override { return inner_.inertial(); }
  const mpm::MpmState& state() const override { return inner_.state(); }
  mpm::MpmState& state() override { return inner_.state(); }

 private:
  Scheme& inner_;
};

TEST(RunLoop, AStepEndingOnTheTargetIsAtTheTargetWhateverTheSchemeSays) {
  const MpmCase c = column_case();
  ExplicitScheme explicit_scheme(c);
  NeverAtTarget scheme(explicit_scheme);
  CountingObserver counter;
  const std::vector<MpmPhaseEnd> ends = run_phases(c, scheme, 0, {&counter});
  ASSERT_EQ(ends.size(), 1u);
  EXPECT_EQ(ends[0].reason, "duration_s");
  ASSERT_EQ(counter.records, 5);
  for (int k = 0; k < 5; ++k) EXPECT_NEAR(counter.record_times[k], 0.005 * k, 1e-15);
  EXPECT_EQ(counter.snapshots, 3);
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
  MpmCase c = column_case();
  c.phases[0].energy_interval = 1e-300;
  expect_error_within_a_minute(c, "energy_interval_s");
}

TEST(RunLoop, AnOutputIntervalFarBelowTheTimeStepIsAnErrorNotAHang) {
  MpmCase c = column_case();
  c.phases[0].output_interval = 1e-300;
  expect_error_within_a_minute(c, "output_interval_s");
}

}  // namespace
}  // namespace pilempm
