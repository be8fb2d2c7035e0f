// `pilempm element ...` run as a user runs it: the binary (PILEMPM_BINARY) in a shell.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>
#include "run_pilempm.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

using pilempm_test::read_text;
using pilempm_test::Result;
using pilempm_test::run_pilempm;

using pilempm::test_support::TestDir;

namespace fs = std::filesystem;

// The number after "key": inside the object "object" of a JSON text (enough for our summaries).
double json_number(const std::string& json, const std::string& object, const std::string& key) {
  const std::size_t at = json.find("\"" + object + "\": {");
  if (at == std::string::npos) return std::nan("");
  const std::size_t k = json.find("\"" + key + "\": ", at);
  if (k == std::string::npos) return std::nan("");
  return std::stod(json.substr(k + key.size() + 4));
}

TEST(ElementCli, TriaxialExampleCommandWritesCurveAndSummary) {
  const TestDir dir("cli");
  // Exactly the command of the issue (2000 steps by default).
  const Result r = run_pilempm(
      "element triaxial --set original --igs IGS3 --e0 0.567 --e0-at zero-pressure "
      "--sigma3-kPa 2000 --axial-strain 0.25 --out '" +
      (dir / "tx.csv") + "' --summary '" + (dir / "tx.json") + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("peak q"), std::string::npos) << r.output;
  const std::string csv = read_text(dir / "tx.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 2 + 2001);
  EXPECT_NE(csv.find("sigma_a_kPa"), std::string::npos);
  const std::string json = read_text(dir / "tx.json");
  const double phi = json_number(json, "peak", "phi_mob_deg");
  EXPECT_GT(phi, 30.0) << json;
  EXPECT_LT(phi, 50.0) << json;
  // The void ratio actually used: 0.567 scaled from zero pressure to p0 = 2 MPa by Bauer's law.
  const double e = json_number(json, "initial", "void_ratio");
  EXPECT_NEAR(e, 0.567 * std::exp(-std::pow(3.0 * 2e6 / 4e9, 0.42)), 1e-9) << json;
  EXPECT_NE(json.find("\"e0_at\": \"zero-pressure\""), std::string::npos);
  for (const auto& entry : fs::directory_iterator(dir.path()))  // no temporary file is left
    EXPECT_NE(entry.path().extension(), ".tmp") << entry.path();
}

TEST(ElementCli, E0AtMustBeGiven) {
  const Result r =
      run_pilempm("element triaxial --set original --igs IGS3 --e0 0.6 --sigma3-kPa 100");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--e0-at"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("initial-stress"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("zero-pressure"), std::string::npos) << r.output;
}

TEST(ElementCli, BadFlagValueNamesFlagValueAndRange) {
  const Result r = run_pilempm(
      "element oedometer --set original --igs IGS3 --e0 0.7 --e0-at initial-stress "
      "--sigma-v0-kPa 10 --K0 0.5 --sigma-v-kPa 400,-100");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--sigma-v-kPa = -100: out of range: must be > 0"), std::string::npos)
      << r.output;
}

TEST(ElementCli, BadKeyInCaseFileNamesFileLineAndKey) {
  const TestDir dir("cli");
  const std::string file = dir / "bad.toml";
  std::ofstream(file) << "[[test]]\nname = \"a\"\ntype = \"triaxial\"\nset = \"original\"\n"
                         "igs = \"IGS3\"\ne0 = 0.6\ne0_at = \"initial-stress\"\n"
                         "sigma3_kPa = 100\naxial_strian = 0.2\n";
  const Result r = run_pilempm("element run '" + file + "' --out '" + (dir / "out") + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find(file + ":9: test[0].axial_strian"), std::string::npos) << r.output;
  // Nothing ran and nothing was written.
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(ElementCli, RunOnlyOneTestOfTheExampleCase) {
  const TestDir dir("cli");
  const std::string example = std::string(PILEMPM_SOURCE_DIR) + "/examples/element_tests.toml";
  const Result r = run_pilempm("element run '" + example +
                               "' --only tx-dense-s3-50kPa-e0.59 --out '" + (dir / "out") + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("[1/1] tx-dense-s3-50kPa-e0.59"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("summary.csv"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(dir / "out/tx-dense-s3-50kPa-e0.59.csv"));
  EXPECT_TRUE(fs::exists(dir / "out/tx-dense-s3-50kPa-e0.59.json"));
  const std::string summary = read_text(dir / "out/summary.csv");
  EXPECT_EQ(std::count(summary.begin(), summary.end(), '\n'), 2);

  const Result unknown = run_pilempm("element run '" + example + "' --only no-such-test --out '" +
                                     (dir / "out2") + "'");
  EXPECT_NE(unknown.exit_code, 0);
  EXPECT_NE(unknown.output.find("tx-hp-s3-30MPa"), std::string::npos) << unknown.output;
}

// The whole built-in example case (about the study's full set of element tests).
TEST(ElementCli, LongRunsTheWholeBuiltInCase) {
  const TestDir dir("cli");
  const Result r = run_pilempm("element run --out '" + (dir / "out") + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string summary = read_text(dir / "out/summary.csv");
  EXPECT_GE(std::count(summary.begin(), summary.end(), '\n'), 31);
  EXPECT_EQ(summary.find("failed"), std::string::npos) << summary;
  EXPECT_TRUE(fs::exists(dir / "out/summary.md"));
  EXPECT_TRUE(fs::exists(dir / "out/case.toml"));
}

}  // namespace
