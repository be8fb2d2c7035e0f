#pragma once
// One centrifuge pile test run (docs/centrifuge.md): the scenario's MPM case is run into
// DIR/mpm/ (particle snapshots, energies, bodies, a checkpoint per phase), and DIR gets what an
// engineer reads: pile.csv (head, tip and shaft force and the tip stress against pile
// displacement and tip depth, with the equilibrium and energy checks), fields_<phase>.csv and
// .vtu at the snapshot depths and phase ends (void ratio, p, q, IGS ρ; the pile's outline in
// fields_<phase>_pile.csv), summary.json and
// summary.md, and the head-force plots.
#include <filesystem>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "pilempm/scenario/centrifuge/centrifuge_scenario.hpp"
#include "pilempm/scenario/centrifuge/experiment.hpp"
#include "pilempm/study/figures.hpp"

namespace pilempm {

struct CentrifugeRunOptions {
  std::string python;                 ///< the interpreter for the plots ("" = the default search)
  bool plots = true;                  ///< draw the PNG figures
  bool progress_on_terminal = false;  ///< the progress stream is a terminal (lines in place)
  /// A checkpoint of a centrifuge run (DIR/mpm/checkpoint_NN_<phase>.h5) to continue from: the
  /// phases after it run, and the outputs (pile.csv, the fields, the summary) hold the whole run
  /// as if it had run from the start. The case must give the same MPM case up to that phase
  /// (only the later phases may differ: MPM-4 continues MPM-3's installation); else
  /// InputError naming the checkpoint.
  std::filesystem::path restart;
};

/// Runs the scenario into `out_dir`; `case_text` (may be empty) is the centrifuge case file's
/// text, kept as DIR/case.toml. Progress lines go to `progress` (nullptr: none).
scenario::CentrifugeSummary run_centrifuge(const scenario::CentrifugeScenario& scenario,
                                           const std::string& case_text,
                                           const std::filesystem::path& out_dir,
                                           std::ostream* progress,
                                           const CentrifugeRunOptions& options = {});

/// Checks, before anything is written, that `checkpoint` can continue the scenario
/// (CentrifugeRunOptions::restart): a readable checkpoint of a centrifuge run, taken at a phase
/// end, of the same MPM case up to there. Throws InputError naming the checkpoint.
void check_centrifuge_restart(const scenario::CentrifugeScenario& s,
                              const std::filesystem::path& checkpoint);

/// The checkpoint at the end of the scenario's installation, relative to its run folder
/// ("mpm/checkpoint_02_installation.h5"); empty when it has no installation.
std::filesystem::path centrifuge_installation_checkpoint(const scenario::CentrifugeScenario& s);

/// The built-in quick case (examples/centrifuge/quick.toml), the README's main job.
std::string_view quick_centrifuge_case_text();

/// The figure of the fields (void ratio, p, q, IGS ρ) around the pile after `phase` of a run of
/// `scenario`, from `csv` (a fields_<phase>.csv; the pile's outline from fields_<phase>_pile.csv
/// beside it), drawn into `file`: each particle as its filled domain, in the zone r <= 5 D (or
/// the container) and from 3 D above to 5 D below the planned tip depth, on fixed colour scales
/// (the same in every run, so that runs compare), the pile drawn over them.
FigureSpec centrifuge_field_figure(const scenario::CentrifugeScenario& scenario,
                                   const std::string& phase, const std::string& csv,
                                   const std::string& file);

/// The column names of pile.csv, in order.
const std::vector<std::string>& centrifuge_pile_columns();

/// summary.json of a run.
std::string centrifuge_summary_json(const scenario::CentrifugeSummary& summary);
/// summary.csv of a run: a header and one row of the numbers of summary.json (nan where none).
std::string centrifuge_summary_csv(const scenario::CentrifugeSummary& summary);

}  // namespace pilempm
