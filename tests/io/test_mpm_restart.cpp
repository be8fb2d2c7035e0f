// Checkpoints and restarts of MPM runs: a run restarted from the checkpoint of its first phase
// ends with the same output as the run that went through, and a restart may use a case whose
// later phases differ.
#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "../support/files.hpp"
#include "../support/mpm_case_texts.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/io/mpm_case.hpp"
#include "pilempm/io/mpm_output.hpp"
#include "pilempm/simulation/case_assembly.hpp"

namespace pilempm {
namespace {

using namespace simulation;

namespace fs = std::filesystem;

using test_support::fresh_temp_path;
using test_support::read_text;

TEST(MpmRestart, RestartFromTheFirstPhaseEndsWithTheSameOutput) {
  const std::string plate_case = test_support::plate_into_block_case();
  const MpmCase c = read_mpm_case_text(plate_case, "case.toml");
  const fs::path whole = fresh_temp_path("mpm-whole");
  const MpmRunSummary full = run_mpm_case(c, whole, nullptr);
  ASSERT_EQ(full.checkpoints.size(), 2u);
  EXPECT_EQ(full.checkpoints[0].filename(), "checkpoint_01_push.h5");
  EXPECT_EQ(full.checkpoints[1].filename(), "checkpoint_02_lift.h5");
  ASSERT_TRUE(fs::exists(full.checkpoints[0]));
  ASSERT_EQ(full.phase_ends.size(), 2u);
  EXPECT_NE(full.phase_ends[1].reason.find("stop_force_y_below_N"), std::string::npos);

  const fs::path second = fresh_temp_path("mpm-restarted");
  const MpmRunSummary part = run_mpm_case(c, second, nullptr, full.checkpoints[0]);
  EXPECT_EQ(part.first_phase, 1u);
  ASSERT_EQ(part.phase_ends.size(), 1u);
  EXPECT_EQ(part.phase_ends[0].phase, "lift");
  EXPECT_EQ(part.steps, full.steps);
  EXPECT_EQ(part.time, full.time);
  EXPECT_EQ(read_text(second / "energies.csv"), read_text(whole / "energies.csv"));
  EXPECT_EQ(read_text(second / "bodies.csv"), read_text(whole / "bodies.csv"));
  // The series lists the earlier snapshots (in the first run's folder) and the new ones.
  const std::string pvd = read_text(second / "particles.pvd");
  EXPECT_NE(pvd.find("pilempm-mpm-whole-"), std::string::npos) << pvd;
  EXPECT_NE(pvd.find("file=\"particles_00003.vtu\""), std::string::npos) << pvd;
  EXPECT_FALSE(fs::exists(second / "particles_00000.vtu"));
  EXPECT_EQ(full.vtu_files.size(), part.vtu_files.size() + 3);  // t = 0, 0.025, 0.05 before

  // A restart after the last phase has nothing to run.
  try {
    run_mpm_case(c, second, nullptr, full.checkpoints[1]);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nothing left to run"), std::string::npos) << e.what();
  }

  // A case whose second phase differs: pushed further instead of lifted.
  std::string text = plate_case;
  text.replace(text.find("velocity_y_m_per_s = 0.1"), 24, "velocity_y_m_per_s = -0.1");
  text.replace(text.find("stop_force_y_below_N = 1000.0"), 29,
               "stop_phase_displacement_y_m = -0.002");
  const MpmCase changed = read_mpm_case_text(text, "changed.toml");
  const fs::path third = fresh_temp_path("mpm-changed");
  const MpmRunSummary other = run_mpm_case(changed, third, nullptr, full.checkpoints[0]);
  ASSERT_EQ(other.phase_ends.size(), 1u);
  EXPECT_NE(other.phase_ends[0].reason.find("displacement y = -0.007 m"), std::string::npos)
      << other.phase_ends[0].reason;
  for (const fs::path& dir : {whole, second, third}) fs::remove_all(dir);
}

}  // namespace
}  // namespace pilempm
