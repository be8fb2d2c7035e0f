#pragma once
// The centrifuge study (docs/study.md §4, docs/centrifuge.md): the case files of
// examples/centrifuge/ in groups (installation for both densities and parameter sets, the load-test
// cases MPM-1..4, the IGS study, the parametric study, stress-dependent α), each run into
// DIR/<case>/, then the figures that compare the runs of a group and DIR/README.md with a table of
// every run.
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

namespace pilempm {

struct CentrifugeStudyCase {
  std::string file;   ///< in the cases folder, e.g. "md_original.toml"
  std::string label;  ///< in legends and tables, e.g. "MPM-2"
};

struct CentrifugeStudyGroup {
  std::string name;  ///< "checks", "installation", "slt", "igs", "parametric", "stress-alpha"
  std::string title;
  std::vector<CentrifugeStudyCase> cases;
};

/// The groups of the study, in the order they run.
const std::vector<CentrifugeStudyGroup>& centrifuge_study_groups();

struct CentrifugeStudyOptions {
  std::filesystem::path cases_dir = "examples/centrifuge";
  std::vector<std::string> groups;  ///< the groups to run; empty: all
  bool resume = false;              ///< keep the runs whose DIR/<case>/summary.csv exists
  bool report_only = false;         ///< run nothing: the comparisons of the runs that exist
  bool plots = true;
  std::string python;
};

/// A run of the study that failed its own checks (scenario/centrifuge/run_checks.hpp).
struct CentrifugeStudyFailure {
  std::string file;                 ///< the case file, e.g. "md_original.toml"
  std::vector<std::string> checks;  ///< each failed check's text
};

/// Runs the study into `out_dir`; progress lines go to `progress` (nullptr: none). Throws
/// InputError naming an unknown group or a case file that is missing or wrong, before any run.
/// Returns the runs of the chosen groups that exist and failed their own checks (README.md
/// marks them FAILED); their results are kept.
std::vector<CentrifugeStudyFailure> run_centrifuge_study(const CentrifugeStudyOptions& options,
                                                         const std::filesystem::path& out_dir,
                                                         std::ostream* progress);

}  // namespace pilempm
