// Output of element tests: curve CSV (units in the header, compression positive), JSON summary,
// summary tables, and atomic writing that never leaves a .tmp or destroys a good file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "../support/files.hpp"
#include "../support/refusing_model.hpp"
#include "pilempm/io/element_case.hpp"
#include "pilempm/io/element_output.hpp"
#include "pilempm/io/element_run.hpp"
#include "pilempm/io/output/atomic_file.hpp"

namespace pilempm {
namespace {

namespace fs = std::filesystem;

using test_support::read_text;
using test_support::TestDir;

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> parts;
  std::stringstream s(line);
  std::string part;
  while (std::getline(s, part, sep)) parts.push_back(part);
  return parts;
}

bool has_tmp_files(const fs::path& dir) {
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().extension() == ".tmp") return true;
  return false;
}

ElementCaseFile small_case() {
  return parse_element_case(R"(
[[test]]
name = "tx"
type = "triaxial"
set = "original"
igs = "IGS3"
e0 = 0.6
e0_at = "initial-stress"
sigma3_kPa = 100
axial_strain = 0.1
steps = 200
)",
                            "small.toml");
}

// A model that fails on its first update.
ModelPtr failing_model() {
  return std::make_shared<test_support::RefusingModel>("failing", "deliberate failure", 1.0);
}

TEST(AtomicWrite, WritesTheFileAndLeavesNoTmp) {
  const TestDir dir("io");
  const fs::path file = dir.path() / "a.csv";
  write_file_atomically(file, "one\n");
  write_file_atomically(file, "two\n");
  EXPECT_EQ(read_text(file), "two\n");
  EXPECT_FALSE(has_tmp_files(dir.path()));
}

TEST(AtomicWrite, FailureLeavesNothingBehind) {
  const TestDir dir("io");
  // The "folder" of the target is a regular file: writing must fail cleanly.
  write_file_atomically(dir.path() / "plain", "x");
  EXPECT_THROW(write_file_atomically(dir.path() / "plain" / "a.csv", "y"), Error);
  EXPECT_EQ(read_text(dir.path() / "plain"), "x");
  EXPECT_FALSE(has_tmp_files(dir.path()));
  EXPECT_THROW(prepare_output_directory(dir.path() / "plain"), Error);
  EXPECT_THROW(check_output_file(dir.path() / "plain" / "b.csv"), Error);
}

TEST(ElementOutput, TriaxialCurveHasUnitsInTheHeaderAndIsCompressionPositive) {
  const TestDir dir("io");
  const ElementCaseFile file = small_case();
  const ElementRunRecord r =
      run_and_write(file.tests[0], dir.path() / "tx.csv", dir.path() / "tx.json");
  ASSERT_TRUE(r.ok) << r.error;
  std::istringstream csv(read_text(dir.path() / "tx.csv"));
  std::string comment, header, first, line, last;
  std::getline(csv, comment);
  std::getline(csv, header);
  std::getline(csv, first);
  int rows = 1;
  while (std::getline(csv, line)) {
    last = line;
    ++rows;
  }
  EXPECT_EQ(comment.rfind("# ", 0), 0u);
  EXPECT_NE(comment.find("compression positive"), std::string::npos);
  const std::vector<std::string> columns = split(header, ',');
  EXPECT_EQ(columns, curve_columns());
  for (const char* name : {"axial_strain_pct", "volumetric_strain_pct", "sigma_a_kPa",
                           "sigma_r_kPa", "p_kPa", "q_kPa", "void_ratio", "phi_mob_deg"})
    EXPECT_NE(std::find(columns.begin(), columns.end(), name), columns.end()) << name;
  EXPECT_EQ(rows, 201);  // the initial state and 200 increments

  const auto column = [&columns](const std::string& name) {
    return static_cast<std::size_t>(std::find(columns.begin(), columns.end(), name) -
                                    columns.begin());
  };
  const std::vector<std::string> start = split(first, ','), end = split(last, ',');
  EXPECT_DOUBLE_EQ(std::stod(start[column("sigma_r_kPa")]), 100.0);  // kPa, compression +
  EXPECT_DOUBLE_EQ(std::stod(start[column("axial_strain_pct")]), 0.0);
  EXPECT_NEAR(std::stod(end[column("axial_strain_pct")]), 10.0, 1e-9);  // percent, compression +
  EXPECT_GT(std::stod(end[column("sigma_a_kPa")]), 200.0);
  EXPECT_GT(std::stod(end[column("q_kPa")]), 100.0);
  EXPECT_NEAR(std::stod(end[column("sigma_r_kPa")]), 100.0, 0.1);
  // Dense sand dilates: the volumetric strain (compression positive) ends negative.
  EXPECT_LT(std::stod(end[column("volumetric_strain_pct")]), 0.0);
  EXPECT_FALSE(has_tmp_files(dir.path()));

  const std::string json = read_text(dir.path() / "tx.json");
  for (const char* part :
       {"\"e0_at\": \"initial-stress\"", "\"void_ratio\": 0.6,", "\"peak_at_end\": false",
        "\"phi_mob_deg\"", "\"name\": \"IGS3\"", "\"sign_convention\": \"compression positive\""})
    EXPECT_NE(json.find(part), std::string::npos) << part << "\n" << json;
}

TEST(ElementOutput, FailedRunDoesNotTouchExistingFiles) {
  const TestDir dir("io");
  ElementCase c = small_case().tests[0];
  c.model = failing_model();
  const fs::path curve = dir.path() / "tx.csv", summary = dir.path() / "tx.json";
  write_file_atomically(curve, "good old curve\n");
  write_file_atomically(summary, "{}\n");
  const ElementRunRecord r = run_and_write(c, curve, summary);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("deliberate failure"), std::string::npos) << r.error;
  EXPECT_EQ(read_text(curve), "good old curve\n");
  EXPECT_EQ(read_text(summary), "{}\n");
  EXPECT_FALSE(has_tmp_files(dir.path()));
}

TEST(ElementOutput, CaseRunWritesEveryFileAndRecordsFailures) {
  const TestDir dir("io");
  ElementCaseFile file = parse_element_case(R"(title = "two tests"
[defaults]
set = "original"
igs = "IGS3"
e0_at = "initial-stress"
[[test]]
name = "iso"
type = "isotropic"
e0 = 0.7
p0_kPa = 10
p_end_kPa = 500
steps = 20
[[test]]
name = "oed"
type = "oedometer"
e0 = 0.7
sigma_v0_kPa = 10
K0 = 0.5
sigma_v_kPa = [200, 50]
steps_per_segment = 20
)",
                                            "two.toml");
  file.tests[1].model = failing_model();
  std::size_t started = 0, finished = 0;
  ElementRunObserver observer;
  observer.started = [&](std::size_t, std::size_t, const ElementCase&) { ++started; };
  observer.finished = [&](std::size_t, std::size_t, const ElementRunRecord&) { ++finished; };
  const ElementRunReport report = run_element_case(file, dir.path() / "out", {}, observer);
  EXPECT_EQ(started, 2u);
  EXPECT_EQ(finished, 2u);
  EXPECT_EQ(report.failures, 1u);
  const fs::path out = dir.path() / "out";
  EXPECT_TRUE(fs::exists(out / "iso.csv"));
  EXPECT_TRUE(fs::exists(out / "iso.json"));
  EXPECT_FALSE(fs::exists(out / "oed.csv"));
  EXPECT_EQ(read_text(out / "case.toml"), file.text);
  const std::string table = read_text(out / "summary.csv");
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 3);
  EXPECT_NE(table.find("iso,isotropic,original,hypoplastic,IGS3,0.7,initial-stress,0.7,10,"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("failed: "), std::string::npos);
  const std::string markdown = read_text(out / "summary.md");
  EXPECT_EQ(markdown.rfind("# two tests", 0), 0u);
  EXPECT_NE(markdown.find("| iso | isotropic | original | IGS3 |"), std::string::npos) << markdown;
  EXPECT_FALSE(has_tmp_files(out));

  // --only selects by name; an unknown name is an input error listing the tests.
  EXPECT_EQ(select_tests(file, {"oed"}).size(), 1u);
  try {
    select_tests(file, {"nope"});
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("iso, oed"), std::string::npos) << e.what();
  }
}

TEST(ElementOutput, SummaryTableTextHasOneLinePerTest) {
  const ElementCaseFile file = small_case();
  const ElementRunRecord r = run_and_write(file.tests[0], {}, {});
  ASSERT_TRUE(r.ok);
  EXPECT_TRUE(r.curve_file.empty());
  const std::string text = summary_table_text({r, r});
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 3);
  EXPECT_NE(text.find("phi peak deg"), std::string::npos);
}

}  // namespace
}  // namespace pilempm
