#include "pilempm/study/centrifuge_study.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>

#include "pilempm/core/error.hpp"
#include "pilempm/io/centrifuge_case.hpp"
#include "pilempm/io/output/atomic_file.hpp"
#include "pilempm/io/output/format.hpp"
#include "pilempm/io/output/output_folder.hpp"
#include "pilempm/io/toml_reader.hpp"
#include "pilempm/scenario/centrifuge/run_checks.hpp"
#include "pilempm/study/centrifuge_run.hpp"
#include "pilempm/study/csv_table.hpp"
#include "pilempm/study/figures.hpp"
#include "pilempm/study/plotting.hpp"
#include "pilempm/study/process_pool.hpp"
#include "pilempm/study/reference_data.hpp"

namespace pilempm {

using namespace scenario;

namespace {

std::string stem(const std::string& file) {
  return std::filesystem::path(file).stem().string();
}

const std::vector<std::string> kColours{"C0", "C1", "C2", "C3", "C4", "C5", "C6", "C7"};

// Head force against `x` (a column of pile.csv) in `phase`, one curve per case.
PanelSpec head_force_panel(const std::string& title, const std::vector<CentrifugeStudyCase>& cases,
                           const std::string& phase, const std::string& x,
                           const std::string& x_label) {
  PanelSpec panel;
  panel.title = title;
  panel.x.label = x_label;
  panel.y.label = "head force [N]";
  for (std::size_t k = 0; k < cases.size(); ++k)
    panel.series.push_back(curve(stem(cases[k].file) + "/pile.csv", {{"phase", phase}}, x,
                                 "head_force_N", cases[k].label,
                                 SeriesStyle{kColours[k % kColours.size()], "-", "", 1.4, 0}));
  return panel;
}

PanelSpec installation_panel(const std::string& title,
                             const std::vector<CentrifugeStudyCase>& cases) {
  return head_force_panel(title, cases, "installation", "pile_displacement_mm",
                          "pile displacement [mm]");
}

PanelSpec load_test_panel(const std::string& title, const std::vector<CentrifugeStudyCase>& cases) {
  return head_force_panel(title, cases, "load-test", "phase_displacement_mm",
                          "pile displacement in the load test [mm]");
}

std::vector<CentrifugeStudyCase> cases_of(const CentrifugeStudyGroup& group,
                                          std::initializer_list<int> indices) {
  std::vector<CentrifugeStudyCase> cases;
  for (int k : indices) cases.push_back(group.cases.at(static_cast<std::size_t>(k)));
  return cases;
}

std::vector<FigureSpec> group_figures(const CentrifugeStudyGroup& group,
                                      const std::filesystem::path& cases_dir) {
  std::vector<FigureSpec> figures;
  FigureSpec f;
  f.title = group.title;
  if (group.name == "installation") {
    f.file = "installation.png";
    f.cols = 2;
    f.width_in = 13.0;
    f.height_in = 5.0;
    f.sharey = true;
    f.panels = {installation_panel("medium dense, e0 = 0.68", cases_of(group, {0, 1, 2})),
                installation_panel("loose, e0 = 0.75", cases_of(group, {3, 4, 5}))};
    figures.push_back(f);
  } else if (group.name == "slt") {
    f.file = "load_tests.png";
    f.panels.push_back(load_test_panel("", group.cases));
    figures.push_back(f);
  } else if (group.name == "igs") {
    f.file = "igs_void_ratio.png";
    f.cols = static_cast<int>(group.cases.size());
    f.width_in = 4.0 * f.cols;
    f.height_in = 6.0;
    for (const CentrifugeStudyCase& c : group.cases) {
      const CentrifugeScenario s = read_centrifuge_case(cases_dir / c.file);
      const std::string dir = stem(c.file);
      PanelSpec panel =
          centrifuge_field_figure(s, "installation", dir + "/fields_installation.csv", "")
              .panels.front();
      panel.title = c.label;
      panel.y.limits = std::pair{0.0, 1e3 * s.pile_diameter * (s.installation_D + 4.0)};
      f.panels.push_back(panel);
    }
    figures.push_back(f);
    FigureSpec forces;
    forces.file = "igs_head_force.png";
    forces.title = group.title;
    forces.panels = {installation_panel("head force", group.cases)};
    figures.push_back(forces);
  } else if (group.name == "parametric") {
    f.file = "parametric.png";
    f.rows = 2;
    f.cols = 3;
    f.width_in = 16.0;
    f.height_in = 9.0;
    f.sharey = true;
    const std::vector<std::pair<std::string, std::initializer_list<int>>> panels{
        {"h_s", {0, 1, 2}},
        {"n", {0, 3, 4}},
        {"alpha", {0, 5, 6}},
        {"e_d0 and e_c0", {0, 7, 8}},
        {"e0", {0, 9, 10}}};
    for (const auto& [title, indices] : panels)
      f.panels.push_back(installation_panel(title, cases_of(group, indices)));
    figures.push_back(f);
  } else if (group.name == "checks") {
    f.file = "checks.png";
    f.cols = 3;
    f.width_in = 19.0;
    f.height_in = 5.0;
    f.panels = {installation_panel("mesh convergence (0.025 m/s)", cases_of(group, {0, 1, 2, 3})),
                installation_panel("jacking speed (D/6; the D/6 curve at 0.025 m/s)",
                                   cases_of(group, {4, 5, 2, 6})),
                installation_panel("jacking speed at depth (H = 35 D, 17 D to 20 D, D/4)",
                                   cases_of(group, {7, 8}))};
    figures.push_back(f);
  } else {
    f.file = "stress_dependent_alpha.png";
    f.cols = 2;
    f.width_in = 12.0;
    f.height_in = 4.8;
    f.panels.push_back(installation_panel("installation", group.cases));
    f.panels.push_back(load_test_panel("static load test", group.cases));
    figures.push_back(f);
  }
  return figures;
}

// A group's figures without the runs in `missing` (their folder names; each series reads a CSV
// file of its run's folder): their curves are dropped, a panel left without curves is dropped
// (a one-row figure narrows by its width), a figure left without panels is not drawn, and the
// titles name the runs left out (`missing_labels`). Colours stay those of the whole group.
std::vector<FigureSpec> without_runs(std::vector<FigureSpec> figures,
                                     const std::set<std::string>& missing,
                                     const std::vector<std::string>& missing_labels) {
  if (missing.empty()) return figures;
  const auto of_missing_run = [&missing](const SeriesSpec& series) {
    const std::filesystem::path csv(series.csv);
    return !csv.empty() && missing.count(csv.begin()->string()) > 0;
  };
  std::vector<FigureSpec> kept;
  for (FigureSpec& f : figures) {
    const std::size_t panels = f.panels.size();
    for (PanelSpec& panel : f.panels) std::erase_if(panel.series, of_missing_run);
    std::erase_if(f.panels, [](const PanelSpec& panel) { return panel.series.empty(); });
    if (f.panels.empty()) continue;
    if (f.rows == 1 && f.cols == static_cast<int>(panels) && f.panels.size() < panels) {
      if (f.width_in > 0.0) f.width_in *= double(f.panels.size()) / double(panels);
      f.cols = static_cast<int>(f.panels.size());
    }
    f.title += fmt::format("\n(without {}: not finished)", fmt::join(missing_labels, ", "));
    kept.push_back(std::move(f));
  }
  return kept;
}

// The run's own checks from the numbers of its summary.csv (a run kept by --resume is judged
// the same as a new one); a column that is missing reads as NaN.
std::vector<CentrifugeCheck> checks_of(const NumericTable& t) {
  const auto number = [&t](const char* column) {
    return t.has(column) && t.rows() > 0 ? t.column(column).back()
                                         : std::numeric_limits<double>::quiet_NaN();
  };
  CentrifugeSummary r;
  r.initial_stress_error = number("initial_stress_error");
  r.installation_tip_depth_D = number("installation_tip_depth_D");
  r.equilibrium_error = number("equilibrium_error");
  r.equilibrium_error_1D = number("equilibrium_error_1D");
  r.max_kinetic_to_work = number("max_kinetic_to_work");
  const double inside = number("particles_in_pile");
  r.particles_in_pile = inside >= 0.0 ? static_cast<std::size_t>(inside) : 0;
  r.min_radius_mm = number("min_radius_mm");
  return centrifuge_checks(r);
}

std::string checks_cell(const std::vector<CentrifugeCheck>& failed) {
  if (failed.empty()) return "pass";
  std::string names;
  for (const CentrifugeCheck& c : failed) names += (names.empty() ? "" : ", ") + c.name;
  return "**FAILED**: " + names;
}

bool listed_already(const std::vector<CentrifugeStudyFailure>& failures, const std::string& file,
                    bool finished = false) {
  return std::any_of(failures.begin(), failures.end(), [&](const CentrifugeStudyFailure& f) {
    return f.file == file && f.finished() == finished;
  });
}

// The groups named in `chosen` (all when empty), in the study's order.
std::vector<const CentrifugeStudyGroup*> chosen_groups(const std::vector<std::string>& chosen) {
  std::vector<std::string> names;
  for (const CentrifugeStudyGroup& g : centrifuge_study_groups()) names.push_back(g.name);
  for (const std::string& name : chosen)
    if (std::find(names.begin(), names.end(), name) == names.end())
      throw InputError("", 0, "--groups", name, fmt::format("one of {}", fmt::join(names, ", ")));
  std::vector<const CentrifugeStudyGroup*> groups;
  for (const CentrifugeStudyGroup& g : centrifuge_study_groups())
    if (chosen.empty() || std::find(chosen.begin(), chosen.end(), g.name) != chosen.end())
      groups.push_back(&g);
  return groups;
}

// The case files of `groups`, each once (a case shared by two groups runs once), in order.
std::vector<std::string> case_files(const std::vector<const CentrifugeStudyGroup*>& groups) {
  std::vector<std::string> files;
  for (const CentrifugeStudyGroup* g : groups)
    for (const CentrifugeStudyCase& c : g->cases)
      if (std::find(files.begin(), files.end(), c.file) == files.end()) files.push_back(c.file);
  return files;
}

// Whether --resume keeps the run of `file`: it finished before (its summary.csv exists).
bool kept_by_resume(const CentrifugeStudyOptions& options, const std::filesystem::path& out_dir,
                    const std::string& file) {
  return options.resume && std::filesystem::exists(out_dir / stem(file) / "summary.csv");
}

// The case whose installation `file` continues (CentrifugeStudyCase::continues), "" if none.
std::string continued_case(const std::string& file) {
  for (const CentrifugeStudyGroup& g : centrifuge_study_groups())
    for (const CentrifugeStudyCase& c : g.cases)
      if (c.file == file && !c.continues.empty()) return c.continues;
  return "";
}

// The checkpoint run `file` (with scenario `s`) continues from in the study folder: the
// installation checkpoint of the case it continues, "" when it continues none.
std::filesystem::path continued_checkpoint(const std::filesystem::path& out_dir,
                                           const std::string& file, const CentrifugeScenario& s) {
  const std::string from = continued_case(file);
  if (from.empty()) return {};
  const std::filesystem::path checkpoint = centrifuge_installation_checkpoint(s);
  return checkpoint.empty() ? checkpoint : out_dir / stem(from) / checkpoint;
}

// continued_checkpoint where that run has written it, else "" (the run starts from the start).
std::filesystem::path written_continued_checkpoint(const std::filesystem::path& out_dir,
                                                   const std::string& file,
                                                   const CentrifugeScenario& s) {
  std::filesystem::path checkpoint = continued_checkpoint(out_dir, file, s);
  if (!checkpoint.empty() && !std::filesystem::exists(checkpoint)) checkpoint.clear();
  return checkpoint;
}

// Every case file read and checked (InputError naming the file), with its text.
std::vector<std::pair<CentrifugeScenario, std::string>> read_cases(
    const CentrifugeStudyOptions& options, const std::vector<std::string>& files) {
  std::vector<std::pair<CentrifugeScenario, std::string>> scenarios;
  for (const std::string& file : files) {
    const std::filesystem::path path = options.cases_dir / file;
    std::string text = read_case_text(path);
    scenarios.emplace_back(read_centrifuge_case_text(text, path.string(), options.analysis),
                           std::move(text));
  }
  return scenarios;
}

void check_program(const CentrifugeStudyOptions& options) {
  if (options.program.empty() || !options.program.is_absolute())
    throw Error(
        fmt::format("the study's child runs need the pilempm program as an absolute path, "
                    "not \"{}\"",
                    options.program.string()));
}

std::filesystem::path absolute_path(const std::filesystem::path& path) {
  return std::filesystem::absolute(path).lexically_normal();
}

// The run of case `file` as a child process, `pilempm centrifuge run` (the same run as the one
// in this process: the same case text into the same folder name); `absolute`: every path
// absolute (a command list run elsewhere), else as given (children of this process).
ChildRun child_run(const CentrifugeStudyOptions& options, const std::filesystem::path& out_dir,
                   const std::string& file, bool absolute,
                   const std::filesystem::path& restart = {}) {
  const auto path = [absolute](const std::filesystem::path& p) {
    return (absolute ? absolute_path(p) : p).string();
  };
  ChildRun run;
  run.name = file;
  run.arguments = {
      options.program.string(),   "centrifuge", "run", path(options.cases_dir / file), "--out",
      path(out_dir / stem(file)), "--overwrite"};
  if (!options.plots) run.arguments.emplace_back("--no-plots");
  if (options.analysis) {
    run.arguments.emplace_back("--analysis");
    run.arguments.emplace_back(to_string(*options.analysis));
  }
  if (!options.python.empty()) {
    run.arguments.emplace_back("--python");
    run.arguments.push_back(options.python);
  }
  if (!restart.empty()) {
    run.arguments.emplace_back("--restart");
    run.arguments.push_back(path(restart));
  }
  run.log = path(out_dir / "logs" / (stem(file) + ".log"));
  return run;
}

// `pilempm centrifuge run`'s exit status for a run that ended and wrote everything but failed
// its own checks (kExitChecksFailed of src/cli/commands.hpp); the study judges those checks
// from the run's summary.csv as it does for a run in this process.
constexpr int kRunFailedItsChecks = 4;

// A child run of case `file` finished: it ended with status 0 or kRunFailedItsChecks and wrote
// its summary.csv.
bool child_finished(const ChildOutcome& outcome, const std::filesystem::path& out_dir,
                    const std::string& file) {
  return outcome.started && (outcome.exit_code == 0 || outcome.exit_code == kRunFailedItsChecks) &&
         std::filesystem::exists(out_dir / stem(file) / "summary.csv");
}

// ": head force X N, capacity Y N" from a run's summary.csv, with the number of its failed
// checks; what went wrong when the file cannot be read.
std::string summary_words(const std::filesystem::path& summary) {
  try {
    const NumericTable t = read_numeric_csv(summary);
    const std::vector<CentrifugeCheck> failed = failed_checks(checks_of(t));
    return fmt::format(
        ": head force {} N, capacity {} N{}", table_cell(t, "installation_head_force_N", "{:.1f}"),
        table_cell(t, "load_test_capacity_N", "{:.1f}"),
        failed.empty() ? std::string() : fmt::format(", FAILED {} of its checks", failed.size()));
  } catch (const Error& e) {
    return fmt::format("; its summary cannot be read: {}", e.what());
  }
}

// Runs the cases `to_run` (indices into `files`) as child processes, options.jobs at once, each
// on one thread; a line per run as it ends. Returns the runs that did not finish, in case order.
std::vector<CentrifugeStudyFailure> run_as_children(
    const CentrifugeStudyOptions& options, const std::filesystem::path& out_dir,
    const std::vector<std::string>& files,
    const std::vector<std::pair<CentrifugeScenario, std::string>>& scenarios,
    const std::vector<std::size_t>& to_run, std::ostream* progress) {
  std::vector<ChildRun> runs;
  for (const std::size_t k : to_run) {
    runs.push_back(child_run(options, out_dir, files[k], false,
                             written_continued_checkpoint(out_dir, files[k], scenarios[k].first)));
  }
  if (runs.empty()) return {};
  prepare_output_directory(out_dir / "logs");
  for (const ChildRun& run : runs) note_output_file(run.log);  // the study's files
  if (progress != nullptr)
    *progress << fmt::format(
                     "study: {} run{}, {} at once, each on one thread; their output in "
                     "{}/\n",
                     runs.size(), runs.size() == 1 ? "" : "s",
                     std::min<std::size_t>(runs.size(), options.jobs), (out_dir / "logs").string())
              << std::flush;
  const auto start = std::chrono::steady_clock::now();
  std::size_t ended = 0;
  double run_seconds = 0.0;
  const auto finished = [&](std::size_t i, const ChildOutcome& outcome) {
    ++ended;
    run_seconds += outcome.wall_seconds;
    if (progress == nullptr) return;
    const std::string count = fmt::format("({}/{})", ended, runs.size());
    if (!child_finished(outcome, out_dir, runs[i].name)) {
      *progress << fmt::format("study: {} did not finish: {} after {:.1f} s {}; its log: {}\n",
                               runs[i].name, outcome.how_it_ended(), outcome.wall_seconds, count,
                               runs[i].log.string())
                << std::flush;
      return;
    }
    *progress << fmt::format("study: {} done in {:.1f} s {}{}\n", runs[i].name,
                             outcome.wall_seconds, count,
                             summary_words(out_dir / stem(runs[i].name) / "summary.csv"))
              << std::flush;
  };
  const std::vector<ChildOutcome> outcomes =
      run_children(runs, options.jobs, {"OMP_NUM_THREADS=1"}, finished);
  if (progress != nullptr)
    *progress << fmt::format(
        "study: {} run{} in {:.1f} s with {} at once (the runs' own times add up to {:.1f} s)\n",
        runs.size(), runs.size() == 1 ? "" : "s",
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
        std::min<std::size_t>(runs.size(), options.jobs), run_seconds);
  std::vector<CentrifugeStudyFailure> unfinished;
  for (std::size_t i = 0; i < runs.size(); ++i)
    if (!child_finished(outcomes[i], out_dir, runs[i].name))
      unfinished.push_back({runs[i].name, {}, outcomes[i].how_it_ended(), runs[i].log});
  return unfinished;
}

// "pilempm study centrifuge --out DIR [--groups ...] [--analysis ...]": how the study's runs
// were asked for (the cases folder only where it is not the default).
std::string study_command(const CentrifugeStudyOptions& options,
                          const std::filesystem::path& out_dir) {
  std::string command = "pilempm study centrifuge --out " + reference_folder_name(out_dir);
  if (options.cases_dir != CentrifugeStudyOptions{}.cases_dir)
    command += " --cases " + options.cases_dir.string();
  if (!options.groups.empty())
    command += fmt::format(" --groups {}", fmt::join(options.groups, ","));
  if (options.analysis) command += fmt::format(" --analysis {}", to_string(*options.analysis));
  return command;
}

// The reference data set of the chosen groups' runs (CentrifugeStudyOptions::reference_data):
// each case file once, with the labels it has in those groups.
void write_reference_data(const CentrifugeStudyOptions& options,
                          const std::filesystem::path& out_dir,
                          const std::vector<const CentrifugeStudyGroup*>& groups,
                          const std::vector<std::string>& files, std::ostream* progress) {
  std::vector<ReferenceDataRun> runs;
  for (std::size_t k = 0; k < files.size(); ++k) {
    ReferenceDataRun run{files[k], {}, 0};
    const std::filesystem::path summary = out_dir / stem(files[k]) / "summary.csv";
    if (std::filesystem::exists(summary))  // judged as README.md judges it
      run.failed_checks = int(failed_checks(checks_of(read_numeric_csv(summary))).size());
    for (const CentrifugeStudyGroup* g : groups)
      for (const CentrifugeStudyCase& c : g->cases)
        if (c.file == files[k] &&
            std::find(run.labels.begin(), run.labels.end(), c.label) == run.labels.end())
          run.labels.push_back(c.label);
    runs.push_back(std::move(run));
  }
  OutputFolderOptions folder;
  folder.overwrite = true;  // the set is replaced as a whole
  const OutputFolderClaim claim = claim_output_folder(options.reference_data, folder);
  const ReferenceDataReport report = write_centrifuge_reference_data(
      out_dir, runs, options.reference_data, options.analysis, study_command(options, out_dir));
  if (progress != nullptr)
    *progress << fmt::format(
        "study: reference data of {} run{} in {}/ ({}{}{})\n", report.written.size(),
        report.written.size() == 1 ? "" : "s", options.reference_data.string(),
        report.readme.filename().string(),
        report.missing.empty() ? std::string()
                               : fmt::format("; not run: {}", fmt::join(report.missing, ", ")),
        claim.removed_files.empty() ? std::string()
                                    : fmt::format("; {} files of the set written before replaced",
                                                  claim.removed_files.size()));
}

}  // namespace

const std::vector<CentrifugeStudyGroup>& centrifuge_study_groups() {
  static const std::vector<CentrifugeStudyGroup> groups{
      {"checks",
       "numerical checks: small model, installation 3 D to 6 D (and 17 D to 20 D)",
       {{"check_mesh_d3.toml", "D/3"},
        {"check_mesh_d4.toml", "D/4"},
        {"check_mesh_d6.toml", "D/6"},
        {"check_mesh_d8.toml", "D/8"},
        {"check_speed_0.1.toml", "D/6 at 0.1 m/s"},
        {"check_speed_0.05.toml", "D/6 at 0.05 m/s"},
        {"check_speed_0.0125.toml", "D/6 at 0.0125 m/s"},
        {"check_depth_0.025.toml", "17 D to 20 D at 0.025 m/s"},
        {"check_depth_0.0125.toml", "17 D to 20 D at 0.0125 m/s"}}},
      {"installation",
       "installation 10 D to 20 D (IGS 3): head force",
       {{"md_original.toml", "medium dense, original"},
        {"md_modified.toml", "medium dense, modified alpha 0.03"},
        {"md_modified_alpha006.toml", "medium dense, modified alpha 0.06"},
        {"loose_original.toml", "loose, original"},
        {"loose_modified.toml", "loose, modified alpha 0.03"},
        {"loose_modified_alpha006.toml", "loose, modified alpha 0.06"}}},
      {"slt",
       "static load tests MPM-1..4 (medium dense)",
       {{"mpm1_wished_in_place.toml", "MPM-1 (wished in place at 20 D, original)"},
        {"md_original.toml", "MPM-2 (installed, original)"},
        {"md_modified.toml", "MPM-3 (installed, modified)"},
        {"mpm4_modified_then_original.toml", "MPM-4 (installed modified, SLT original)",
         "md_modified.toml"},
        {"mpm2_mohr_coulomb.toml", "MPM-2 with Mohr-Coulomb sand"}}},
      {"igs",
       "IGS study: small model (R = 6 D), installation to 4.7 D",
       {{"igs1_small.toml", "IGS 1"},
        {"igs2_small.toml", "IGS 2"},
        {"igs3_small.toml", "IGS 3"},
        {"igs4_small.toml", "IGS 4"}}},
      {"parametric",
       "parametric study: small model, installation 5 D to 10 D, original set varied",
       {{"par_base.toml", "original set"},
        {"par_hs2000.toml", "h_s = 2000 MPa"},
        {"par_hs8000.toml", "h_s = 8000 MPa"},
        {"par_n0.32.toml", "n = 0.32"},
        {"par_n0.52.toml", "n = 0.52"},
        {"par_alpha0.06.toml", "alpha = 0.06"},
        {"par_alpha0.18.toml", "alpha = 0.18"},
        {"par_emin_emax_low.toml", "e_d0 = 0.51, e_c0 = 0.88"},
        {"par_emin_emax_high.toml", "e_d0 = 0.59, e_c0 = 0.97"},
        {"par_e0_0.62.toml", "e0 = 0.62"},
        {"par_e0_0.75.toml", "e0 = 0.75"}}},
      {"stress-alpha",
       "stress-dependent alpha (docs/study.md §5) against the original set",
       {{"md_original.toml", "original, alpha = 0.12"},
        {"md_stress_dependent_alpha.toml", "original, stress-dependent alpha"}}},
  };
  return groups;
}

std::vector<CentrifugeStudyFailure> run_centrifuge_study(const CentrifugeStudyOptions& options,
                                                         const std::filesystem::path& out_dir,
                                                         std::ostream* progress) {
  const std::vector<const CentrifugeStudyGroup*> groups = chosen_groups(options.groups);
  // Every case file is read and checked before the first run.
  const std::vector<std::string> files = case_files(groups);
  const std::vector<std::pair<CentrifugeScenario, std::string>> scenarios =
      read_cases(options, files);
  if (options.jobs > 1 && !options.report_only) check_program(options);
  prepare_output_directory(out_dir);

  std::vector<std::size_t> to_run;  // report only: run nothing
  for (std::size_t k = 0; k < (options.report_only ? 0 : files.size()); ++k) {
    if (kept_by_resume(options, out_dir, files[k])) {
      if (progress != nullptr)
        *progress << fmt::format("study: {} done before, kept ({}/{})\n", files[k], k + 1,
                                 files.size());
      continue;
    }
    to_run.push_back(k);
  }
  std::vector<CentrifugeStudyFailure> unfinished;
  if (options.jobs > 1) {
    // A run that continues another's installation waits for it when that one runs too.
    std::vector<std::size_t> first, then;
    for (const std::size_t k : to_run) {
      const std::string from = continued_case(files[k]);
      const bool waits =
          !from.empty() && std::any_of(to_run.begin(), to_run.end(),
                                       [&](std::size_t j) { return files[j] == from; });
      (waits ? then : first).push_back(k);
    }
    unfinished = run_as_children(options, out_dir, files, scenarios, first, progress);
    for (CentrifugeStudyFailure& f :
         run_as_children(options, out_dir, files, scenarios, then, progress))
      unfinished.push_back(std::move(f));
    const auto index = [&](const CentrifugeStudyFailure& f) {
      return std::find(files.begin(), files.end(), f.file) - files.begin();
    };
    std::stable_sort(unfinished.begin(), unfinished.end(),
                     [&](const auto& a, const auto& b) { return index(a) < index(b); });
  } else {
    for (const std::size_t k : to_run) {
      const std::filesystem::path dir = out_dir / stem(files[k]);
      const std::filesystem::path restart =
          written_continued_checkpoint(out_dir, files[k], scenarios[k].first);
      if (progress != nullptr)
        *progress << fmt::format("study: running {} ({}/{}){}\n", files[k], k + 1, files.size(),
                                 restart.empty()
                                     ? std::string()
                                     : fmt::format(", from {}'s installation ({})",
                                                   continued_case(files[k]), restart.string()))
                  << std::flush;
      // The case's folder is the study's own: what an earlier, unfinished run of the case left
      // there is replaced.
      OutputFolderOptions folder;
      folder.overwrite = true;
      claim_output_folder(dir, folder);
      CentrifugeRunOptions run_options;
      run_options.plots = options.plots;
      run_options.python = options.python;
      run_options.restart = restart;
      const CentrifugeSummary s =
          run_centrifuge(scenarios[k].first, scenarios[k].second, dir, progress, run_options);
      const std::vector<CentrifugeCheck> failed = failed_checks(centrifuge_checks(s));
      if (progress != nullptr)
        *progress << fmt::format(
            "study: {} done in {:.1f} s: head force {:.1f} N, capacity "
            "{:.1f} N{}\n",
            files[k], s.wall_seconds, s.installation_head_force, s.capacity,
            failed.empty() ? std::string()
                           : fmt::format(", FAILED {} of its checks", failed.size()));
    }
  }

  // The comparisons and the table.
  std::vector<CentrifugeStudyFailure> failures;
  std::vector<FigureSpec> figures;
  std::string readme =
      "# Centrifuge study\n\nEach run is in its folder (`<case>/summary.md`, "
      "`pile.csv`, plots); the figures here compare the runs of a group. Forces "
      "of the full pile; the head force at the end of installation is the mean "
      "over the last cell of travel.\n";
  if (options.analysis)
    readme +=
        fmt::format("Every run: the {} analysis (`--analysis`), whatever its case file says.\n",
                    to_string(*options.analysis));
  for (const CentrifugeStudyGroup* g : groups) {
    // A group's figures draw the runs that finished (with report_only or after a failed run some
    // may not have).
    std::set<std::string> missing;
    std::vector<std::string> missing_labels;
    for (const CentrifugeStudyCase& c : g->cases)
      if (!std::filesystem::exists(out_dir / stem(c.file) / "summary.csv")) {
        missing.insert(stem(c.file));
        missing_labels.push_back(c.label);
      }
    if (missing.size() < g->cases.size())
      for (FigureSpec& f :
           without_runs(group_figures(*g, options.cases_dir), missing, missing_labels))
        figures.push_back(std::move(f));
    readme += fmt::format("\n## {}\n\n", g->title);
    if (missing.size() == g->cases.size())
      readme += "No run of this group has finished: no figure.\n\n";
    else if (!missing.empty())
      readme += fmt::format(
          "Not every run of this group finished: its figures draw the {} of {} that did.\n\n",
          g->cases.size() - missing.size(), g->cases.size());
    readme +=
        "| run | case file | head force end of installation [N] | peak tip stress [MPa] | "
        "SLT capacity at 0.1 D [N] | head-force scatter over the last D [%] | equilibrium error "
        "[%] | kinetic / work [%] | wall time [s] | checks |\n|---|---|---|---|---|---|---|---|---|"
        "---|\n";
    for (const CentrifugeStudyCase& c : g->cases) {
      const std::filesystem::path file = out_dir / stem(c.file) / "summary.csv";
      const auto not_finished =
          std::find_if(unfinished.begin(), unfinished.end(),
                       [&c](const CentrifugeStudyFailure& f) { return f.file == c.file; });
      if (not_finished != unfinished.end() && !listed_already(failures, c.file))
        failures.push_back(*not_finished);
      if (!std::filesystem::exists(file)) {
        readme += not_finished == unfinished.end()
                      ? fmt::format("| {} | `{}` | not run | | | | | | | |\n", c.label, c.file)
                      : fmt::format(
                            "| {} | `{}` | **did not finish**: {} (log `{}`) | | | | | "
                            "| | |\n",
                            c.label, c.file, not_finished->ended,
                            not_finished->log.lexically_relative(out_dir).string());
        continue;
      }
      const NumericTable t = read_numeric_csv(file);
      const std::vector<CentrifugeCheck> failed = failed_checks(checks_of(t));
      readme += fmt::format("| {} | `{}` | {} | {} | {} | {} | {} | {} | {} | {} |\n", c.label,
                            c.file, table_cell(t, "installation_head_force_N", "{:.1f}"),
                            table_cell(t, "peak_tip_stress_MPa", "{:.2f}"),
                            table_cell(t, "load_test_capacity_N", "{:.1f}"),
                            table_cell(t, "scatter_last_D", "{:.2f}", 100.0),
                            table_cell(t, "equilibrium_error", "{:.2f}", 100.0),
                            table_cell(t, "max_kinetic_to_work", "{:.3f}", 100.0),
                            table_cell(t, "wall_time_s", "{:.0f}"), checks_cell(failed));
      if (!failed.empty() && !listed_already(failures, c.file, true)) {
        CentrifugeStudyFailure failure{c.file, {}, "", {}};
        for (const CentrifugeCheck& check : failed) failure.checks.push_back(check.text());
        failures.push_back(std::move(failure));
      }
    }
  }
  write_file_atomically(out_dir / "plot_figures.py", plot_script_text());
  write_file_atomically(out_dir / "figures.json", figures_json(figures));
  readme += "\nFigures: ";
  for (const FigureSpec& f : figures) readme += fmt::format("`{}` ", f.file);
  readme += "(drawn by `/usr/bin/python3 plot_figures.py figures.json` in this folder).\n";
  write_file_atomically(out_dir / "README.md", readme);
  if (!options.reference_data.empty())
    write_reference_data(options, out_dir, groups, files, progress);
  if (options.plots && !figures.empty()) {
    const PlotOutcome plots =
        draw_figures(out_dir / "plot_figures.py", out_dir / "figures.json", options.python);
    if (!plots.plotted && progress != nullptr)
      *progress << fmt::format("study: the figures were not drawn: {}\n", plots.problem);
  }
  return failures;
}

std::size_t write_centrifuge_study_commands(const CentrifugeStudyOptions& options,
                                            const std::filesystem::path& out_dir,
                                            const std::filesystem::path& file) {
  const std::vector<std::string> files = case_files(chosen_groups(options.groups));
  const std::vector<std::pair<CentrifugeScenario, std::string>> scenarios =
      read_cases(options, files);  // every case file checked before anything runs
  check_program(options);
  prepare_output_directory(out_dir / "logs");
  const auto kept = [&](const std::string& case_file) {
    return kept_by_resume(options, out_dir, case_file);
  };
  // One line per run. A run that continues another's installation follows that one on its
  // line when it is in the list, from its checkpoint where that run wrote one (whether or not
  // it then passed its checks) and else from the start:
  //   A; if [ -f CHECKPOINT ]; then B --restart CHECKPOINT; else B; fi
  // When that run is kept (--resume), it starts from the checkpoint if there is one.
  // One thread per run unless the environment says otherwise (a Slurm task with several CPUs:
  // OMP_NUM_THREADS=$SLURM_CPUS_PER_TASK).
  const std::vector<std::string> environment{"OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}"};
  std::vector<std::string> lines_of(files.size());
  std::vector<std::pair<std::size_t, std::string>> following;  // (source, its continuation)
  for (std::size_t k = 0; k < files.size(); ++k) {
    if (kept(files[k])) continue;
    const std::filesystem::path restart =
        continued_checkpoint(out_dir, files[k], scenarios[k].first);
    const auto source = std::find(files.begin(), files.end(), continued_case(files[k]));
    const bool follows = !restart.empty() && source != files.end() && !kept(*source);
    const ChildRun plain = child_run(options, out_dir, files[k], true);
    note_output_file(plain.log);  // written by the shell, a file of the study
    if (!follows) {
      lines_of[k] = shell_command(std::filesystem::exists(restart)
                                      ? child_run(options, out_dir, files[k], true, restart)
                                      : plain,
                                  environment);
      continue;
    }
    following.emplace_back(
        std::size_t(source - files.begin()),
        fmt::format(
            "; if [ -f {} ]; then {}; else {}; fi", shell_word(absolute_path(restart).string()),
            shell_command(child_run(options, out_dir, files[k], true, restart), environment),
            shell_command(plain, environment)));
  }
  for (const auto& [source, continuation] : following) lines_of[source] += continuation;
  std::string text;
  std::size_t lines = 0;
  for (const std::string& line : lines_of)
    if (!line.empty()) {
      text += line + "\n";
      ++lines;
    }
  write_file_atomically(file, text);
  return lines;
}

}  // namespace pilempm
