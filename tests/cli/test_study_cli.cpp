// `pilempm study calibration` run as a user runs it: the binary (PILEMPM_BINARY) in a shell.
// The full check of the outputs is tests/study/test_calibration_study.cpp; here the command
// line: its flags, its messages, and what it does without a Python that can plot.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>
#include "run_pilempm.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

using pilempm::test_support::TestDir;
using pilempm_test::read_text;
using pilempm_test::Result;
using pilempm_test::run_pilempm;

namespace fs = std::filesystem;

TEST(StudyCli, WithoutPythonItWarnsAndStillWritesEverythingElse) {
  const TestDir dir("study-cli", false);  // the command makes it
  const Result r = run_pilempm("study calibration --quick --python /nonexistent/python3 --out '" +
                               dir.path().string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Progress lines while it runs, then a clear warning with what to do.
  EXPECT_NE(r.output.find("item 8/8"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("pilempm: warning: the figures were not drawn"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("/nonexistent/python3"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("python3-matplotlib"), std::string::npos) << r.output;
  for (const char* file :
       {"README.md", "figures.json", "plot_figures.py", "oedometer.csv", "high_pressure_table.csv",
        "alpha_pressure.csv", "stress_dependent_alpha_table.csv", "tests/case.toml"})
    EXPECT_GT(fs::file_size(dir.path() / file), 0u) << file;
  EXPECT_FALSE(fs::exists(dir.path() / "oedometer.png"));
  const std::string readme = read_text(dir.path() / "README.md");
  EXPECT_NE(readme.find("**The figures were not drawn**"), std::string::npos);
  EXPECT_NE(readme.find("/usr/bin/python3 plot_figures.py figures.json"), std::string::npos);
}

TEST(StudyCli, OutIsRequiredAndABadFolderIsAnError) {
  Result r = run_pilempm("study calibration --quick");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--out"), std::string::npos) << r.output;

  const TestDir dir("study-cli", false);  // the command makes it
  fs::create_directories(dir.path());
  std::ofstream(dir.path() / "a-file") << "x";
  r = run_pilempm("study calibration --quick --no-plots --out '" +
                  (dir.path() / "a-file" / "out").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("pilempm: error: output folder"), std::string::npos) << r.output;
}

TEST(StudyCli, HelpListsTheFlags) {
  const Result r = run_pilempm("study calibration --help");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  for (const char* flag : {"--out", "--quick", "--no-plots", "--python"})
    EXPECT_NE(r.output.find(flag), std::string::npos) << flag;
}

}  // namespace
