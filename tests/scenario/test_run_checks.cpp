// The verdict of a centrifuge run's own checks (scenario/centrifuge/run_checks.hpp): a run within
// the limits of docs/verification.md §8 passes, each quantity past its limit fails its own check
// and no other, a NaN where the check applies fails, and a run without installation is not
// judged on the installation's checks.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "../support/centrifuge_summaries.hpp"
#include "pilempm/scenario/centrifuge/run_checks.hpp"

namespace pilempm::scenario {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

CentrifugeSummary good_run() {
  return pilempm_test::summary_of_a_good_centrifuge_run();
}

std::vector<std::string> failed_names(const CentrifugeSummary& r) {
  std::vector<std::string> names;
  for (const CentrifugeCheck& c : failed_checks(centrifuge_checks(r))) names.push_back(c.name);
  return names;
}

TEST(CentrifugeRunChecks, AGoodRunPassesEveryCheck) {
  const std::vector<CentrifugeCheck> checks = centrifuge_checks(good_run());
  ASSERT_EQ(checks.size(), 5u);
  for (const CentrifugeCheck& c : checks) {
    EXPECT_TRUE(c.applies) << c.text();
    EXPECT_TRUE(c.passed) << c.text();
  }
  EXPECT_TRUE(failed_checks(checks).empty());
}

TEST(CentrifugeRunChecks, EachQuantityPastItsLimitFailsItsOwnCheck) {
  CentrifugeSummary r = good_run();
  r.initial_stress_error = 0.0101;
  EXPECT_EQ(failed_names(r), std::vector<std::string>{"K0 stress"});
  r = good_run();
  r.equilibrium_error_1D = 1.0685;  // the 1000 g, 10 m/s run
  EXPECT_EQ(failed_names(r), std::vector<std::string>{"equilibrium"});
  r = good_run();
  r.max_kinetic_to_work = 0.14073;
  EXPECT_EQ(failed_names(r), std::vector<std::string>{"kinetic energy"});
  r = good_run();
  r.particles_in_pile = 3;
  EXPECT_EQ(failed_names(r), std::vector<std::string>{"sand in the pile"});
  r = good_run();
  r.min_radius_mm = -0.1;
  EXPECT_EQ(failed_names(r), std::vector<std::string>{"axis"});
  // At the limits themselves they pass.
  r = good_run();
  r.initial_stress_error = kMaxInitialStressError;
  r.equilibrium_error_1D = kMaxEquilibriumError;
  r.max_kinetic_to_work = kMaxKineticToWork;
  EXPECT_TRUE(failed_names(r).empty());
}

TEST(CentrifugeRunChecks, TheFailedCheckSaysWhatItMeasuredAndItsLimit) {
  CentrifugeSummary r = good_run();
  r.equilibrium_error_1D = 1.0685;
  const std::vector<CentrifugeCheck> failed = failed_checks(centrifuge_checks(r));
  ASSERT_EQ(failed.size(), 1u);
  const std::string text = failed.front().text();
  EXPECT_NE(text.find("equilibrium"), std::string::npos) << text;
  EXPECT_NE(text.find("106."), std::string::npos) << text;
  EXPECT_NE(text.find("limit 2 %"), std::string::npos) << text;
  EXPECT_NE(text.find("1 D"), std::string::npos) << text;
}

TEST(CentrifugeRunChecks, NanWhereACheckAppliesFails) {
  CentrifugeSummary r = good_run();
  r.initial_stress_error = kNaN;
  r.equilibrium_error_1D = kNaN;
  r.equilibrium_error = kNaN;  // forces that became NaN during the installation
  EXPECT_EQ(failed_names(r), (std::vector<std::string>{"K0 stress", "equilibrium"}));
}

TEST(CentrifugeRunChecks, ShortInstallationIsJudgedOverOneCellWindows) {
  CentrifugeSummary r = good_run();
  r.equilibrium_error_1D = kNaN;  // less than 1 D of travel with a head force
  r.max_kinetic_to_work = kNaN;   // measured only after the first D of travel
  r.equilibrium_error = 0.019;
  std::vector<CentrifugeCheck> checks = centrifuge_checks(r);
  EXPECT_TRUE(failed_checks(checks).empty());
  EXPECT_NE(checks[1].text().find("one cell"), std::string::npos) << checks[1].text();
  EXPECT_FALSE(checks[2].applies) << checks[2].text();
  r.equilibrium_error = 0.021;
  EXPECT_EQ(failed_names(r), std::vector<std::string>{"equilibrium"});
}

TEST(CentrifugeRunChecks, ARunWithoutInstallationIsNotJudgedOnIt) {
  CentrifugeSummary r = good_run();  // MPM-1: wished in place, load test only
  r.installation_head_force = r.installation_tip_depth_D = kNaN;
  r.equilibrium_error = r.equilibrium_error_1D = r.max_kinetic_to_work = kNaN;
  const std::vector<CentrifugeCheck> checks = centrifuge_checks(r);
  EXPECT_TRUE(failed_checks(checks).empty());
  EXPECT_FALSE(checks[1].applies);
  EXPECT_FALSE(checks[2].applies);
  EXPECT_TRUE(checks[0].applies);  // the K0 stress is still checked
}

}  // namespace
}  // namespace pilempm::scenario
