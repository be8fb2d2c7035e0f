// What the commands do at the end of a run and with their output folder, as a user sees it:
// a centrifuge run that fails its own checks prints FAILED, says so in its summary, keeps its
// results and exits with status 4, a normal one exits 0; an output folder that holds another
// run is refused (status 2) unless --overwrite, which removes only that run's files; a restart
// into its own folder still works; stray temporary files are removed with a line saying so; a
// full disk is an error that leaves no temporary file.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "run_pilempm.hpp"

namespace {

namespace fs = std::filesystem;
using pilempm_test::read_text;
using pilempm_test::Result;
using pilempm_test::run_pilempm;

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

class RunStatusCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = pilempm::test_support::fresh_test_path("run-status");
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  // No temporary file of pilempm's in `folder` or below.
  static void expect_no_temporary_files(const fs::path& folder) {
    for (const auto& entry : fs::recursive_directory_iterator(folder))
      EXPECT_NE(entry.path().extension(), ".tmp") << "left behind: " << entry.path();
  }
  fs::path dir_;
};

// A tiny centrifuge model (R = 4 D, H = 8 D, D/2 mesh, pile from 2 D jacked 1.5 D): seconds.
std::string tiny_centrifuge_case(const std::string& test_lines, const std::string& jacking) {
  return "title = \"tiny\"\n[test]\ncontainer_radius_D = 4.0\nsand_height_D = 8.0\n" + test_lines +
         "\n[sand]\nmaterial = \"original\"\nigs = \"IGS3\"\ne0 = 0.68\ne0_at = "
         "\"initial-stress\"\n"
         "[installation]\nwished_in_place_D = 2.0\ndepth_D = 1.5\n" +
         jacking +
         "\n[mesh]\ncells_per_D = 2\nfine_radius_D = 2.0\nfine_depth_below_tip_D = 2.0\n"
         "headroom_D = 1.0\n[solver]\nthreads = 1\n";
}

TEST_F(RunStatusCli, ACentrifugeRunThatFailsItsOwnChecksSaysFailedKeepsItsResultsAndExitsFour) {
  // The absurd but valid physics: 1000 g and a pile jacked at 10 m/s.
  const fs::path file =
      write("absurd.toml", tiny_centrifuge_case("g_level = 1000.0", "velocity_m_per_s = 10.0"));
  const fs::path out = dir_ / "absurd";
  const std::string command =
      "centrifuge run '" + file.string() + "' --out '" + out.string() + "' --quiet --no-plots";
  Result r = run_pilempm(command, 600);
  ASSERT_EQ(r.exit_code, 4) << r.output;
  EXPECT_TRUE(contains(r.output, "\nFAILED: ")) << r.output;
  EXPECT_TRUE(contains(r.output, "pilempm: FAILED: the run failed")) << r.output;
  // What was computed is kept, and the summary says FAILED.
  EXPECT_GT(fs::file_size(out / "pile.csv"), 0u);
  EXPECT_TRUE(contains(read_text(out / "summary.md"), "**FAILED:"))
      << read_text(out / "summary.md");
  EXPECT_TRUE(contains(read_text(out / "summary.json"), "\"checks\": \"FAILED\""));
  expect_no_temporary_files(out);

  // The same folder again is refused, naming it, and changes nothing.
  const auto pile_time = fs::last_write_time(out / "pile.csv");
  std::ofstream(out / "my-notes.txt") << "mine\n";
  r = run_pilempm(command, 600);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "holds the files of another run")) << r.output;
  EXPECT_TRUE(contains(r.output, out.string())) << r.output;
  EXPECT_EQ(fs::last_write_time(out / "pile.csv"), pile_time);

  // --overwrite removes that run's files first (the snapshots of mpm/ too), not the user's; a
  // stray temporary file of a run that was killed is removed with a line saying so.
  std::ofstream(out / "mpm" / "particles_99999.vtu") << "an old snapshot\n";
  std::ofstream(out / "mpm" / "energies.csv.999999999-3.tmp") << "half written\n";
  r = run_pilempm(command + " --overwrite", 600);
  EXPECT_EQ(r.exit_code, 4) << r.output;
  EXPECT_TRUE(contains(r.output, "--overwrite: removed the")) << r.output;
  EXPECT_TRUE(contains(r.output, "removed 1 temporary file")) << r.output;
  EXPECT_FALSE(fs::exists(out / "mpm" / "particles_99999.vtu"));
  EXPECT_FALSE(fs::exists(out / "mpm" / "energies.csv.999999999-3.tmp"));
  EXPECT_EQ(read_text(out / "my-notes.txt"), "mine\n");
  EXPECT_GT(fs::file_size(out / "pile.csv"), 0u);
}

TEST_F(RunStatusCli, ANormalCentrifugeRunPassesItsChecksAndExitsZero) {
  const fs::path file = write("normal.toml", tiny_centrifuge_case("", ""));
  const fs::path out = dir_ / "normal";
  const Result r = run_pilempm(
      "centrifuge run '" + file.string() + "' --out '" + out.string() + "' --quiet --no-plots",
      600);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "checks: PASS")) << r.output;
  EXPECT_FALSE(contains(r.output, "FAILED")) << r.output;
  EXPECT_TRUE(contains(read_text(out / "summary.md"), "**Checks: PASS**"));
  EXPECT_TRUE(contains(read_text(out / "summary.json"), "\"checks\": \"PASS\""));
  expect_no_temporary_files(out);
}

TEST_F(RunStatusCli, HelpListsTheExitStatuses) {
  const Result r = run_pilempm("--help");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "4 FAILED")) << r.output;
  const Result run = run_pilempm("centrifuge run --help");
  EXPECT_TRUE(contains(run.output, "--overwrite")) << run.output;
}

// A short version of the example column: two phases with a checkpoint each.
std::string short_column_case() {
  std::string text =
      read_text(std::string(PILEMPM_SOURCE_DIR) + "/examples/mpm/column_self_weight.toml");
  const auto at = text.find("[[phase]]");
  return text.substr(0, at) +
         "[[phase]]\nname = \"one\"\nduration_s = 0.02\n[[phase]]\nname = \"two\"\n"
         "duration_s = 0.02\n";
}

TEST_F(RunStatusCli, MpmRunRefusesAnotherRunsFolderAndRestartsInItsOwn) {
  const fs::path file = write("column.toml", short_column_case());
  const fs::path out = dir_ / "column";
  const std::string run = "mpm run '" + file.string() + "' --out '" + out.string() + "' --quiet";
  Result r = run_pilempm(run, 300);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(out / "checkpoint_01_one.h5"));
  EXPECT_TRUE(contains(read_text(out / ".pilempm-files"), "checkpoint_01_one.h5\n"));

  r = run_pilempm(run, 300);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "holds the files of another run")) << r.output;

  // A restart from the folder's own checkpoint continues there.
  r = run_pilempm(run + " --restart '" + (out / "checkpoint_01_one.h5").string() + "'", 300);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "restarted from")) << r.output;
  // ... but not with --overwrite, which would remove the checkpoint it reads.
  r = run_pilempm(run + " --overwrite --restart '" + (out / "checkpoint_01_one.h5").string() + "'",
                  300);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(fs::exists(out / "checkpoint_01_one.h5"));
  // A restart into a folder that holds another run is refused.
  const fs::path other = dir_ / "other";
  ASSERT_EQ(
      run_pilempm("mpm run '" + file.string() + "' --out '" + other.string() + "' --quiet", 300)
          .exit_code,
      0);
  r = run_pilempm("mpm run '" + file.string() + "' --out '" + other.string() +
                      "' --quiet --restart '" + (out / "checkpoint_01_one.h5").string() + "'",
                  300);
  EXPECT_EQ(r.exit_code, 2) << r.output;

  r = run_pilempm(run + " --overwrite", 300);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  expect_no_temporary_files(out);
}

// `pilempm ARGUMENTS` under a file-size limit of `kib` KiB (SIGXFSZ ignored, so a write past it
// fails with EFBIG as on a full disk).
Result run_on_a_small_disk(int kib, const std::string& arguments) {
  return run_pilempm(arguments, 0, "trap '' XFSZ; ulimit -f " + std::to_string(kib) + "; ");
}

// A disk that fills during the run (64 KiB: the small files fit, a checkpoint does not) stops it
// with an error naming the file and leaves no temporary file; so does a disk that is full from
// the start (the list of the run's files cannot be written).
TEST_F(RunStatusCli, AFullDiskStopsAnMpmRunWithAnErrorAndNoTemporaryFile) {
  const fs::path file = write("column.toml", short_column_case());
  for (const int kib : {64, 0}) {
    const fs::path out = dir_ / ("full-" + std::to_string(kib));
    const Result r = run_on_a_small_disk(
        kib, "mpm run '" + file.string() + "' --out '" + out.string() + "' --quiet");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, out.string())) << r.output;
    expect_no_temporary_files(out);
  }
}

TEST_F(RunStatusCli, ElementRunCalibrateAndStudiesRefuseAFolderWithAnotherRun) {
  const fs::path out = dir_ / "taken";
  fs::create_directories(out / "mpm");
  std::ofstream(out / "particles.pvd") << "<VTKFile/>\n";
  std::ofstream(out / "mpm" / "energies.csv") << "time_s\n";
  for (const std::string& command :
       {"element run --only " + std::string("oed-original-e0.70") + " --out '" + out.string() + "'",
        "calibrate '" + std::string(PILEMPM_SOURCE_DIR) +
            "/examples/calibration/baskarp.toml' --out '" + out.string() + "' --no-plots",
        "study calibration --quick --no-plots --out '" + out.string() + "'",
        "study centrifuge --groups checks --no-plots --out '" + out.string() + "'"}) {
    const Result r = run_pilempm(command, 120);
    EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, "holds the files of another run")) << command << "\n"
                                                                      << r.output;
  }
  EXPECT_TRUE(fs::exists(out / "particles.pvd"));
}

// A study continues in its own folder with --resume and --report-only, without --overwrite.
TEST_F(RunStatusCli, AStudyContinuesInItsOwnFolder) {
  const fs::path out = dir_ / "study";
  const std::string report = "study centrifuge --groups checks --report-only --no-plots --out '" +
                             out.string() + "' --cases '" + PILEMPM_SOURCE_DIR +
                             "/examples/centrifuge'";
  Result r = run_pilempm(report, 120);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_pilempm(report, 120);  // its README.md and figures.json are the study's own
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = run_pilempm(report + " --overwrite", 120);
  EXPECT_EQ(r.exit_code, 2) << r.output;  // --overwrite would remove the runs it reports
  EXPECT_TRUE(contains(r.output, "--overwrite")) << r.output;
}

TEST_F(RunStatusCli, ElementRunOverwritesOnlyWhenAskedAndKeepsForeignFiles) {
  const fs::path out = dir_ / "element";
  const std::string run = "element run --only oed-original-e0.70 --out '" + out.string() + "'";
  Result r = run_pilempm(run, 300);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ofstream(out / "mine.csv") << "1\n";
  r = run_pilempm(run, 300);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = run_pilempm(run + " --overwrite", 300);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_text(out / "mine.csv"), "1\n");
  // A full disk: an error naming the folder, no temporary file.
  r = run_on_a_small_disk(0, run + " --overwrite");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, out.string())) << r.output;
  expect_no_temporary_files(out);
}

}  // namespace

namespace {

// calibrate's numbers are checked like those of the other commands (they were taken at any
// magnitude: a noise of 1e-300 passed its range [0, 1]).
TEST(CommandLineValues, CalibrateFlagsAreCheckedForRangeAndMagnitude) {
  const fs::path dir =
      fs::temp_directory_path() / ("pilempm-calibrate-flags-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  // A copy of the example, so that nothing could write the example's data.
  fs::copy_file(std::string(PILEMPM_SOURCE_DIR) + "/examples/calibration/baskarp.toml",
                dir / "case.toml", fs::copy_options::overwrite_existing);
  const std::string make = "calibrate '" + (dir / "case.toml").string() + "' --make-data original";
  for (const auto& [flags, option] :
       {std::pair<std::string, std::string>{" --noise 1e-300", "--noise"},
        {" --noise 1e300", "--noise"},
        {" --noise nan", "--noise"},
        {" --noise 2", "--noise"},
        {" --seed -1", "--seed"},
        {" --seed 99999999999999999999", "--seed"}}) {
    const Result r = run_pilempm(make + flags, 60);
    EXPECT_NE(r.exit_code, 0) << flags << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, option)) << flags << "\n" << r.output;
    EXPECT_FALSE(contains(r.output, "wrote ")) << flags << "\n" << r.output;
  }
  const Result r = run_pilempm("calibrate '" + (dir / "case.toml").string() + "' --out '" +
                                   (dir / "out").string() + "' --threads 0",
                               60);
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "--threads")) << r.output;
  fs::remove_all(dir);
}

}  // namespace
