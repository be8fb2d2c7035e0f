#pragma once
// The centrifuge study (docs/study.md §4, docs/centrifuge.md): the case files of
// examples/centrifuge/ in groups (installation for both densities and parameter sets, the load-test
// cases MPM-1..4, the IGS study, the parametric study, stress-dependent α), each run into
// DIR/<case>/, then the figures that compare the runs of a group and DIR/README.md with a table of
// every run.
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "pilempm/simulation/mpm_case.hpp"

namespace pilempm {

struct CentrifugeStudyCase {
  CentrifugeStudyCase(std::string file_name, std::string legend, std::string continued = {})
      : file(std::move(file_name)), label(std::move(legend)), continues(std::move(continued)) {}
  std::string file;   ///< in the cases folder, e.g. "md_original.toml"
  std::string label;  ///< in legends and tables, e.g. "MPM-2"
  /// The case whose installation this run continues (`pilempm centrifuge run --restart` from
  /// its installation checkpoint; its MPM case up to there must be this one's), run before it;
  /// from the start when that checkpoint does not exist. Empty: from the start.
  std::string continues;
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
  /// Runs at once. 1: one after the other in this process (each on the threads of its case
  /// file, `[solver] threads`). More: each run a child process `program centrifuge run CASE
  /// --out DIR/<case> --overwrite` with OMP_NUM_THREADS=1, its output in DIR/logs/<case>.log.
  int jobs = 1;
  /// The pilempm program for the child runs and the command list (an absolute path).
  std::filesystem::path program;
  /// The analysis of every run whatever its case file's `[solver] analysis` says (`--analysis`;
  /// the child runs and the command list get it too); none: each case file's own.
  std::optional<simulation::MpmAnalysis> analysis;
  /// Where the reference data set of the chosen groups' finished runs goes after the report
  /// (`--reference-data`; study/reference_data.hpp): the folder is taken for it (the files of
  /// the set written there before are replaced); empty: none.
  std::filesystem::path reference_data;
};

/// A run of the study that failed its own checks (scenario/centrifuge/run_checks.hpp), or, with
/// jobs > 1, a child run that did not finish (`ended` says how; `checks` is then empty).
struct CentrifugeStudyFailure {
  std::string file;                 ///< the case file, e.g. "md_original.toml"
  std::vector<std::string> checks;  ///< each failed check's text
  std::string ended;                ///< a run that did not finish: "exit code 2", ...; else ""
  std::filesystem::path log;        ///< that run's log file
  bool finished() const { return ended.empty(); }
};

/// Runs the study into `out_dir`; progress lines go to `progress` (nullptr: none; with jobs > 1
/// one line as each run ends, in the order they end). Throws InputError naming an unknown group
/// or a case file that is missing or wrong, before any run. Returns, in the order of the study's
/// cases, the runs that did not finish (jobs > 1; the others still run) and the runs of the
/// chosen groups that exist and failed their own checks (README.md marks both); their results
/// are kept. A run that continues another's installation (CentrifugeStudyCase::continues: MPM-4
/// from MPM-3's) runs after it, from its installation checkpoint when that exists (with jobs > 1
/// in a second round of child runs), else from the start.
std::vector<CentrifugeStudyFailure> run_centrifuge_study(const CentrifugeStudyOptions& options,
                                                         const std::filesystem::path& out_dir,
                                                         std::ostream* progress);

/// The runs of the study as a command list: one shell command line per case file of the chosen
/// groups (without those kept by `resume`), in the study's order, each `program centrifuge run
/// CASE --out DIR/<case> --overwrite` with absolute paths and its output into
/// DIR/logs/<case>.log, one thread per run unless OMP_NUM_THREADS is set; a run that continues
/// another's installation (CentrifugeStudyCase::continues) follows that one on its line
/// (`A; if [ -f CHECKPOINT ]; then B --restart CHECKPOINT; else B; fi`), or starts from its
/// checkpoint when that run is kept. GNU parallel
/// (`parallel -j N < FILE`) or a Slurm job array (line $SLURM_ARRAY_TASK_ID) runs them; then
/// run_centrifuge_study with report_only gathers them. Reads and checks every case file first
/// (InputError), creates DIR/logs/, writes `file` (atomically) and returns the number of lines.
std::size_t write_centrifuge_study_commands(const CentrifugeStudyOptions& options,
                                            const std::filesystem::path& out_dir,
                                            const std::filesystem::path& file);

}  // namespace pilempm
