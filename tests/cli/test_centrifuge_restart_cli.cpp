// `pilempm centrifuge run CASE --restart DIR/mpm/checkpoint_NN_<phase>.h5`: a run continued
// from a checkpoint of a centrifuge run writes what the whole run writes (pile.csv, the fields,
// the MPM records, the summary but its wall time), whether it continues its own run or another
// run whose MPM case is the same up to that phase (MPM-4 from MPM-3's installation: only the
// load test's set differs); a case that differs before the checkpoint, a checkpoint of a plain
// MPM run and a missing file are errors naming the checkpoint, before the output folder is touched.
// Tiny quasi-static cases (R = 4 D, D/2, 0.5 D of installation, relaxation, 0.05 D load test; 173
// particles, about a second).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "run_pilempm.hpp"
#include "tiny_centrifuge_case.hpp"

namespace {

using pilempm_test::read_text;
using pilempm_test::Result;
using pilempm_test::run_pilempm;
using pilempm_test::summary_without_wall_time;
using pilempm_test::tiny_centrifuge_case;

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("pilempm-restart-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

Result run_case(const fs::path& file, const fs::path& out, const std::string& more = "") {
  return run_pilempm("centrifuge run '" + file.string() + "' --out '" + out.string() +
                     "' --no-plots --quiet " + more);
}

// The files of a run that a restarted run must write the same.
void expect_same_run(const fs::path& whole, const fs::path& restarted) {
  for (const char* file :
       {"pile.csv", "fields_installation.csv", "fields_installation_pile.csv",
        "fields_installation.vtu", "fields_load-test.csv", "mpm/bodies.csv", "mpm/energies.csv"})
    EXPECT_EQ(read_text(restarted / file), read_text(whole / file)) << file;
  ASSERT_NE(read_text(whole / "summary.csv").find("wall_time_s"), std::string::npos);
  EXPECT_EQ(summary_without_wall_time(read_text(restarted / "summary.csv")),
            summary_without_wall_time(read_text(whole / "summary.csv")));
}

TEST(CentrifugeRestartCli, AContinuedRunWritesTheWholeRun) {
  const fs::path dir = fresh_dir("whole");
  const fs::path a = dir / "a.toml", b = dir / "b.toml";
  std::ofstream(a) << tiny_centrifuge_case("tiny A",
                                           "material = \"modified-medium-dense\"\ne0 = 0.68\n");
  // B: A with the original set in the load test (MPM-4 to A's MPM-3).
  std::ofstream(b) << tiny_centrifuge_case(
      "tiny B",
      "material = \"modified-medium-dense\"\ne0 = 0.68\nload_test_material = \"original\"\n");
  ASSERT_EQ(run_case(a, dir / "A").exit_code, 0);
  ASSERT_EQ(run_case(b, dir / "B").exit_code, 0);
  const fs::path installed = dir / "A" / "mpm" / "checkpoint_02_installation.h5";
  ASSERT_TRUE(fs::exists(installed));

  // A from its own installation, into another folder: the whole run again.
  Result r = run_case(a, dir / "A2", "--restart '" + installed.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_same_run(dir / "A", dir / "A2");
  EXPECT_NE(read_text(dir / "A2" / "summary.md").find("Continued from the checkpoint"),
            std::string::npos);

  // B from A's installation: B's whole run, though B's own installation never ran; its load
  // test differs from A's (the original set).
  r = run_case(b, dir / "B2", "--restart '" + installed.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_same_run(dir / "B", dir / "B2");
  EXPECT_NE(read_text(dir / "B" / "pile.csv"), read_text(dir / "A" / "pile.csv"));

  // A continuing itself in its own folder from its relaxation (the folder's files are kept).
  r = run_case(a, dir / "A2",
               "--restart '" + (dir / "A2" / "mpm" / "checkpoint_03_relaxation.h5").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_same_run(dir / "A", dir / "A2");
  fs::remove_all(dir);
}

TEST(CentrifugeRestartCli, ACheckpointThatCannotContinueTheCaseIsAnErrorNamingIt) {
  const fs::path dir = fresh_dir("refused");
  const fs::path a = dir / "a.toml", c = dir / "c.toml";
  std::ofstream(a) << tiny_centrifuge_case("tiny A",
                                           "material = \"modified-medium-dense\"\ne0 = 0.68\n");
  std::ofstream(c) << tiny_centrifuge_case(
      "tiny C", "material = \"modified-medium-dense\"\ne0 = 0.70\n");  // another installation
  ASSERT_EQ(run_case(a, dir / "A").exit_code, 0);
  const fs::path installed = dir / "A" / "mpm" / "checkpoint_02_installation.h5";

  Result r = run_case(c, dir / "C", "--restart '" + installed.string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(installed.string()), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("differs from this case's"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("density_kg_per_m3"), std::string::npos) << r.output;
  // Checked before the output folder is touched: none is made, and an old one given with
  // --overwrite keeps its files.
  EXPECT_FALSE(fs::exists(dir / "C"));
  const std::string kept = read_text(dir / "A" / "summary.csv");
  r = run_case(c, dir / "A", "--overwrite --restart '" + installed.string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(read_text(dir / "A" / "summary.csv"), kept);

  // A checkpoint of `pilempm mpm run` has no centrifuge record.
  ASSERT_EQ(run_pilempm("mpm run '" + (dir / "A" / "mpm_case.toml").string() + "' --out '" +
                        (dir / "M").string() + "' --quiet")
                .exit_code,
            0);
  r = run_case(a, dir / "D",
               "--restart '" + (dir / "M" / "checkpoint_02_installation.h5").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("not written by a centrifuge run"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "D"));

  r = run_case(a, dir / "E", "--restart '" + (dir / "none.h5").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("no such checkpoint file"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "E"));
  fs::remove_all(dir);
}

}  // namespace
