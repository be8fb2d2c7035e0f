// A run of the study that continues another's installation (MPM-4 from MPM-3's,
// CentrifugeStudyCase::continues): serially, as child runs (--jobs 2, where it waits for the
// other in a second round) and from the command list (on its source's line, after it), it starts
// from the installation checkpoint of that run and writes what a run of its case from the start
// writes. The cases are five tiny quasi-static ones (R = 4 D, D/2, 0.5 D of installation,
// relaxation and a 0.05 D load test; about a second each) under the names of the `slt` group's
// case files; the tiny MPM-4 is the tiny MPM-3 with the original set in the load test.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "run_pilempm.hpp"
#include "tiny_centrifuge_case.hpp"

namespace {

using pilempm_test::read_text;
using pilempm_test::Result;
using pilempm_test::run_pilempm;
using pilempm_test::run_shell;
using pilempm_test::summary_without_wall_time;
using pilempm_test::tiny_centrifuge_case;

namespace fs = std::filesystem;

std::string quoted(const fs::path& path) {
  std::string text = "'";
  text += path.string();
  text += "'";
  return text;
}

const std::map<std::string, std::string> kCases{
    {"mpm1_wished_in_place", "material = \"original\"\ne0 = 0.64\n"},
    {"md_original", "material = \"original\"\ne0 = 0.68\n"},
    {"md_modified", "material = \"modified-medium-dense\"\ne0 = 0.68\n"},
    {"mpm4_modified_then_original",
     "material = \"modified-medium-dense\"\ne0 = 0.68\nload_test_material = \"original\"\n"},
    {"mpm2_mohr_coulomb", "material = \"original\"\ne0 = 0.71\n"}};

// The files of the tiny MPM-4 run in `dir` that must equal those of a run from the start.
void expect_same_as(const fs::path& dir, const fs::path& whole) {
  for (const char* file : {"pile.csv", "fields_installation.csv", "fields_load-test.csv",
                           "mpm/bodies.csv", "mpm/energies.csv"})
    EXPECT_EQ(read_text(dir / file), read_text(whole / file)) << dir / file;
  EXPECT_EQ(summary_without_wall_time(read_text(dir / "summary.csv")),
            summary_without_wall_time(read_text(whole / "summary.csv")));
  EXPECT_NE(read_text(dir / "summary.md").find("Continued from the checkpoint"), std::string::npos)
      << dir;
}

class StudyContinuedCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() /
                        ("pilempm-study-continued-" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_ / "cases");
    for (const auto& [name, sand] : kCases)
      std::ofstream(*dir_ / "cases" / (name + ".toml"))
          << tiny_centrifuge_case("tiny " + name, sand);
    // The tiny MPM-4 from the start.
    whole_ = new Result(run_pilempm(
        "centrifuge run " + quoted(*dir_ / "cases" / "mpm4_modified_then_original.toml") +
            " --no-plots --quiet --out " + quoted(whole()),
        300));
  }
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(*dir_, ec);
    delete whole_;
    delete dir_;
  }
  void SetUp() override { ASSERT_EQ(whole_->exit_code, 0) << whole_->output; }
  static std::string study_flags() {
    return "study centrifuge --groups slt --no-plots --cases " + quoted(*dir_ / "cases");
  }
  static fs::path whole() { return *dir_ / "mpm4-whole"; }
  static fs::path* dir_;
  static Result* whole_;
};

fs::path* StudyContinuedCli::dir_ = nullptr;
Result* StudyContinuedCli::whole_ = nullptr;

TEST_F(StudyContinuedCli, SeriallyMpm4ContinuesMpm3sInstallation) {
  const fs::path out = *dir_ / "serial";
  const Result r = run_pilempm(study_flags() + " --out " + quoted(out), 300);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("study: running mpm4_modified_then_original.toml (4/5), from "
                          "md_modified.toml's installation"),
            std::string::npos)
      << r.output;
  expect_same_as(out / "mpm4_modified_then_original", whole());
}

TEST_F(StudyContinuedCli, AsChildRunsMpm4WaitsForMpm3AndContinuesIt) {
  const fs::path out = *dir_ / "jobs2";
  const Result r = run_pilempm(study_flags() + " --jobs 2 --out " + quoted(out), 300);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("4 runs, 2 at once"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("1 run, 1 at once"), std::string::npos) << r.output;
  EXPECT_NE(read_text(out / "logs" / "mpm4_modified_then_original.log").find("continues from"),
            std::string::npos);
  expect_same_as(out / "mpm4_modified_then_original", whole());
}

TEST_F(StudyContinuedCli, TheCommandListPutsMpm4OnMpm3sLineFromItsCheckpoint) {
  const fs::path out = *dir_ / "commands";
  const fs::path commands = *dir_ / "commands.txt";
  Result r = run_pilempm(
      study_flags() + " --out " + quoted(out) + " --write-commands " + quoted(commands), 120);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::vector<std::string> lines;
  std::ifstream in(commands);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 4u);
  int chained = 0;
  for (const std::string& line : lines) {
    if (line.find("; if [ -f ") == std::string::npos) continue;
    ++chained;
    // MPM-3, then MPM-4 from its installation checkpoint where MPM-3 wrote it, else from the
    // start.
    const std::size_t mpm3 = line.find("md_modified.toml");
    const std::size_t mpm4 = line.find("mpm4_modified_then_original.toml");
    ASSERT_NE(mpm3, std::string::npos) << line;
    EXPECT_LT(mpm3, mpm4) << line;
    const std::size_t test = line.find("; if [ -f ");
    const std::size_t checkpoint = line.find("md_modified/mpm/checkpoint_02_installation.h5");
    const std::size_t then = line.find(" ]; then ");
    EXPECT_LT(test, checkpoint) << line;
    EXPECT_LT(checkpoint, then) << line;
    EXPECT_NE(line.find("--restart"), std::string::npos) << line;
    EXPECT_NE(line.find("; else "), std::string::npos) << line;
  }
  EXPECT_EQ(chained, 1);
  // Each line as a Slurm array task would run it, one after the other.
  for (const std::string& line : lines) {
    std::ofstream(*dir_ / "line.sh") << line << "\n";
    r = run_shell("bash " + quoted(*dir_ / "line.sh"));
    ASSERT_EQ(r.exit_code, 0) << line << "\n" << r.output;
  }
  r = run_pilempm(study_flags() + " --report-only --out " + quoted(out), 120);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_same_as(out / "mpm4_modified_then_original", whole());
}

}  // namespace
