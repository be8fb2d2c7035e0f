// Output and record intervals far below the time step (1e-300 s): `pilempm mpm run` once spun
// forever at t = 0 with them (the loop counted output times that added nothing to the time).
// Each run here is a separate process under `timeout`, so a loop that does not end fails the
// test (exit status 124) instead of hanging the suite.
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

// The example column with one line of its [[phase]] table added.
fs::path column_case_with(const std::string& phase_line, const std::string& name) {
  std::string text =
      read_text(std::string(PILEMPM_SOURCE_DIR) + "/examples/mpm/column_self_weight.toml");
  const auto at = text.find("[[phase]]");
  EXPECT_NE(at, std::string::npos);
  // Drop the example's own intervals, then add ours right after the header.
  std::string out;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(start, end - start);
    if (line.rfind("output_interval_s", 0) != 0 && line.rfind("energy_interval_s", 0) != 0)
      out += line + "\n";
    if (line == "[[phase]]") out += phase_line + "\n";
    start = end + 1;
  }
  const fs::path file = fs::temp_directory_path() /
                        ("pilempm-interval-" + name + "-" + std::to_string(::getpid()) + ".toml");
  std::ofstream(file) << out;
  return file;
}

void expect_clear_error(const std::string& key) {
  const fs::path file = column_case_with(key + " = 1e-300", key);
  const fs::path out = fs::temp_directory_path() /
                       ("pilempm-interval-out-" + key + "-" + std::to_string(::getpid()));
  const Result r = run_pilempm("mpm run '" + file.string() + "' --out '" + out.string() + "'", 120);
  EXPECT_NE(r.exit_code, 124) << "did not end: " << r.output;
  EXPECT_NE(r.exit_code, 0) << r.output;
  // The file, the key and the smallest value allowed.
  EXPECT_NE(r.output.find(file.filename().string()), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(key), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("1e-300"), std::string::npos) << r.output;
  fs::remove(file);
  fs::remove_all(out);
}

TEST(MpmIntervalsCli, AnOutputIntervalFarBelowTheTimeStepIsAnErrorNotAHang) {
  expect_clear_error("output_interval_s");
}

TEST(MpmIntervalsCli, AnEnergyIntervalFarBelowTheTimeStepIsAnErrorNotAHang) {
  expect_clear_error("energy_interval_s");
}

}  // namespace
