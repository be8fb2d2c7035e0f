// A centrifuge study says which of its runs failed their own checks: each run is judged from its
// summary.csv (a run kept by --resume the same as a new one), README.md marks it FAILED, and
// run_centrifuge_study returns it with the failed checks' texts (the command then exits 4).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "../support/centrifuge_summaries.hpp"
#include "pilempm/io/output/atomic_file.hpp"
#include "pilempm/study/centrifuge_run.hpp"
#include "pilempm/study/centrifuge_study.hpp"

namespace pilempm {
namespace {

namespace fs = std::filesystem;
using scenario::CentrifugeSummary;

TEST(CentrifugeStudyChecks, RunsThatFailTheirChecksAreNamedAndMarkedInTheReadme) {
  const fs::path dir =
      fs::temp_directory_path() / ("pilempm-study-checks-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  // Two runs of the checks group exist: D/3 passes, D/4 failed its equilibrium and kinetic energy.
  fs::create_directories(dir / "check_mesh_d3");
  fs::create_directories(dir / "check_mesh_d4");
  write_file_atomically(dir / "check_mesh_d3" / "summary.csv",
                        centrifuge_summary_csv(pilempm_test::summary_of_a_good_centrifuge_run()));
  CentrifugeSummary bad = pilempm_test::summary_of_a_good_centrifuge_run();
  bad.equilibrium_error_1D = 1.0685;
  bad.max_kinetic_to_work = 0.14;
  write_file_atomically(dir / "check_mesh_d4" / "summary.csv", centrifuge_summary_csv(bad));

  CentrifugeStudyOptions options;
  options.cases_dir = fs::path(PILEMPM_SOURCE_DIR) / "examples" / "centrifuge";
  options.groups = {"checks"};
  options.report_only = true;
  options.plots = false;
  const std::vector<CentrifugeStudyFailure> failed = run_centrifuge_study(options, dir, nullptr);
  ASSERT_EQ(failed.size(), 1u);
  EXPECT_EQ(failed.front().file, "check_mesh_d4.toml");
  ASSERT_EQ(failed.front().checks.size(), 2u);
  EXPECT_NE(failed.front().checks[0].find("equilibrium"), std::string::npos);
  EXPECT_NE(failed.front().checks[1].find("kinetic energy"), std::string::npos);

  std::ifstream in(dir / "README.md");
  const std::string readme((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(readme.find("**FAILED**: equilibrium, kinetic energy |"), std::string::npos) << readme;
  EXPECT_NE(readme.find("| pass |"), std::string::npos) << readme;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pilempm
