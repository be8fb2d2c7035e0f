// The `pilempm analytic ...` subcommands, run as a user would: through the built binary.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

struct CommandResult {
  int exit_code;
  std::string output;  // stdout and stderr together
};

// `shell_prefix` runs before the program in the same shell (e.g. to set a limit).
CommandResult run_pilempm(const std::string& arguments, const std::string& shell_prefix = "") {
  const std::string command =
      shell_prefix + "\"" + std::string(PILEMPM_BINARY) + "\" " + arguments + " 2>&1";
  std::FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return {-1, "popen failed"};
  std::string output;
  char buffer[4096];
  std::size_t count;
  while ((count = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, count);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The brief's Bolton table (I_D = 0.95, phi_c = 31 deg) as printed, three decimals.
TEST(AnalyticCli, BoltonPrintsTheBriefTable) {
  const CommandResult run = run_pilempm(
      "analytic bolton --id 0.95 --phi-c-deg 31 --p-kPa 500,2000,4000,6000,16000,30000");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  for (const char* header : {"p_kPa", "I_R", "phi_max_deg", "psi_max_deg"})
    EXPECT_TRUE(contains(run.output, header)) << header << " missing in\n" << run.output;
  for (const char* value : {"2.596", "38.788", "16.277", "-1.294", "27.119", "-13.930"})
    EXPECT_TRUE(contains(run.output, value)) << value << " missing in\n" << run.output;
}

// Bolton's relation holds for 0 <= I_R <= 4: the rows outside say so, and stderr warns.
TEST(AnalyticCli, BoltonSaysWhenAStressIsOutsideTheRangeOfValidity) {
  const CommandResult inside = run_pilempm("analytic bolton --id 0.95 --phi-c-deg 31 --p-kPa 500");
  ASSERT_EQ(inside.exit_code, 0) << inside.output;
  EXPECT_FALSE(contains(inside.output, "warning")) << inside.output;
  EXPECT_FALSE(contains(inside.output, "outside")) << inside.output;
  // I_R = -1.294 at 30 MPa, 0.95 (10 - ln 1) - 1 = 8.5 at 1 kPa.
  const CommandResult run =
      run_pilempm("analytic bolton --id 0.95 --phi-c-deg 31 --p-kPa 1,500,30000");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(contains(run.output, "I_R < 0: outside Bolton's range")) << run.output;
  EXPECT_TRUE(contains(run.output, "I_R > 4: outside Bolton's range")) << run.output;
  EXPECT_TRUE(contains(run.output, "warning: --p-kPa 1,30000: outside the range of validity"))
      << run.output;
}

TEST(AnalyticCli, BoltonWritesCsvWithUnitsInColumnNames) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("pilempm_test_bolton_" + std::to_string(::getpid()) + ".csv");
  const CommandResult run = run_pilempm(
      "analytic bolton --id 0.95 --phi-c-deg 31 --p-kPa 500,30000 --csv \"" + path.string() + "\"");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::ifstream file(path);
  ASSERT_TRUE(file) << "no CSV at " << path;
  std::string header, first, second, extra;
  std::getline(file, header);
  std::getline(file, first);
  std::getline(file, second);
  EXPECT_FALSE(std::getline(file, extra));
  EXPECT_EQ(header, "p_kPa,I_R,phi_max_deg,dilatancy_rate,sin_psi_max,psi_max_deg,status");
  EXPECT_EQ(first.rfind("500,2.59", 0), 0u) << first;
  EXPECT_EQ(second.rfind("30000,-1.29", 0), 0u) << second;
  std::filesystem::remove(path);
}

TEST(AnalyticCli, BadRelativeDensityExitsNonZeroNamingTheKey) {
  const CommandResult run = run_pilempm("analytic bolton --id 1.5 --phi-c-deg 31 --p-kPa 500");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_TRUE(contains(run.output, "--id")) << run.output;
  EXPECT_TRUE(contains(run.output, "1.5")) << run.output;
}

TEST(AnalyticCli, NegativePressureExitsNonZeroNamingTheKey) {
  const CommandResult run = run_pilempm("analytic bolton --id 0.5 --phi-c-deg 31 --p-kPa 100,-5");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_TRUE(contains(run.output, "--p-kPa")) << run.output;
}

TEST(AnalyticCli, RohePrintsValuesAt10MPa) {
  const CommandResult run = run_pilempm("analytic rohe --sigma-v-MPa 10");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  for (const char* value : {"0.887", "0.524", "1.020"})
    EXPECT_TRUE(contains(run.output, value)) << value << " missing in\n" << run.output;
}

TEST(AnalyticCli, BauerNeedsASetOrAllParameters) {
  const CommandResult with_set = run_pilempm("analytic bauer --set original --p-kPa 0,100");
  ASSERT_EQ(with_set.exit_code, 0) << with_set.output;
  EXPECT_TRUE(contains(with_set.output, "0.9290")) << with_set.output;  // e_c0 at p = 0
  const CommandResult partial = run_pilempm("analytic bauer --h-s-MPa 4000 --n 0.42");
  EXPECT_NE(partial.exit_code, 0);
  EXPECT_TRUE(contains(partial.output, "--e-d0")) << partial.output;
}

TEST(AnalyticCli, AlphaShowsValueAndNoPeak) {
  const CommandResult run =
      run_pilempm("analytic alpha --set original --e0 0.68 --p-kPa 100,10000");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(contains(run.output, "0.1297")) << run.output;
  EXPECT_TRUE(contains(run.output, "no_peak")) << run.output;
}

TEST(AnalyticCli, UnknownSetNamesTheKnownOnes) {
  const CommandResult run = run_pilempm("analytic alpha --set nonsense --e0 0.68");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_TRUE(contains(run.output, "nonsense")) << run.output;
  EXPECT_TRUE(contains(run.output, "original")) << run.output;
}

}  // namespace

namespace {

// A full disk, as the file-size limit makes it for this one command (the signal it would send is
// ignored, so write() fails with EFBIG): the CSV cannot be written. Before the atomic, checked
// writer the command exited 0 and left an empty file.
TEST(AnalyticCli, CsvOnAFullDiskIsAnErrorAndKeepsTheOldFile) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("pilempm_test_full_" + std::to_string(::getpid()) + ".csv");
  std::ofstream(path) << "old\n";
  const CommandResult run = run_pilempm(
      "analytic bolton --id 0.95 --phi-c-deg 31 --p-kPa 100 --csv \"" + path.string() + "\"",
      "trap '' XFSZ; ulimit -f 0; ");
  EXPECT_NE(run.exit_code, 0) << run.output;
  EXPECT_TRUE(contains(run.output, path.string())) << run.output;
  std::ifstream file(path);
  std::string first;
  std::getline(file, first);
  EXPECT_EQ(first, "old");
  for (const auto& entry : std::filesystem::directory_iterator(path.parent_path()))
    EXPECT_FALSE(entry.path().filename().string().starts_with(path.filename().string() + "."))
        << "left behind: " << entry.path();
  std::filesystem::remove(path);
}

}  // namespace

namespace {

// Empty values were taken as 0 (numbers) or the default (names).
TEST(CommandLineValues, EmptyValuesAreRefusedNamingTheOption) {
  for (const char* arguments :
       {"analytic bolton --id \"\" --phi-c-deg 31 --p-kPa 100",
        "analytic bolton --id= "
        "--phi-c-deg 31 --p-kPa 100",
        "element triaxial --set original --igs none --e0 0.7 --e0-at initial-stress "
        "--sigma3-kPa 100 --tolerance \"\""}) {
    const CommandResult run = run_pilempm(arguments);
    EXPECT_NE(run.exit_code, 0) << arguments << "\n" << run.output;
    EXPECT_TRUE(contains(run.output, "empty value")) << arguments << "\n" << run.output;
  }
  const CommandResult id = run_pilempm("analytic bolton --id \"\" --phi-c-deg 31 --p-kPa 100");
  EXPECT_TRUE(contains(id.output, "--id")) << id.output;
}

// Values that pass a plain range check but overflow once converted (1e306 kPa is infinite in Pa).
TEST(CommandLineValues, ValuesThatOverflowInSiAreRefusedAtTheirOption) {
  const CommandResult element = run_pilempm(
      "element triaxial --set original --igs none --e0 0.7 --e0-at initial-stress "
      "--sigma3-kPa 1e306");
  EXPECT_NE(element.exit_code, 0) << element.output;
  EXPECT_TRUE(contains(element.output, "--sigma3-kPa = 1e306: out of range")) << element.output;
  const CommandResult bolton = run_pilempm("analytic bolton --id 0.5 --phi-c-deg 31 --p-kPa 1e306");
  EXPECT_NE(bolton.exit_code, 0) << bolton.output;
  EXPECT_TRUE(contains(bolton.output, "--p-kPa")) << bolton.output;
  EXPECT_TRUE(contains(bolton.output, "magnitude")) << bolton.output;
}

TEST(CommandLineValues, ControlCharactersInValuesAreEscaped) {
  const CommandResult run =
      run_pilempm("analytic bolton --id \"$(printf '\\033[31m')\" --phi-c-deg 31");
  EXPECT_NE(run.exit_code, 0) << run.output;
  EXPECT_FALSE(contains(run.output, "\x1b")) << run.output;
  EXPECT_TRUE(contains(run.output, "\\x1B[31m")) << run.output;
}

// 400 MPa lies beyond where Rohe's fit gives positive void ratios: formerly a negative e_d0
// without a word.
TEST(AnalyticCli, RoheSaysWhenAStressIsOutsideTheRangeOfValidity) {
  const CommandResult run = run_pilempm("analytic rohe --sigma-v-MPa 10,400");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(contains(run.output, "warning: --sigma-v-MPa 400: outside the range of validity"))
      << run.output;
  std::istringstream lines(run.output);
  std::string line;
  int outside = 0;
  while (std::getline(lines, line)) {
    if (contains(line, "400") && contains(line, "outside the range of validity") &&
        !contains(line, "warning"))
      ++outside;
  }
  EXPECT_EQ(outside, 1) << run.output;
}

}  // namespace
