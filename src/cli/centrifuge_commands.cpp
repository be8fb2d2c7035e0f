// `pilempm centrifuge ...`: the centrifuge pile test (docs/centrifuge.md). `run` reads a
// centrifuge case file (or takes the built-in quick case), builds the MPM case, runs it and
// writes the pile's forces, the fields, the summary and the plots; `case` prints the MPM case a
// centrifuge case file becomes.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include "cli/commands.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/io/centrifuge_case.hpp"
#include "pilempm/io/output/format.hpp"
#include "pilempm/io/toml_reader.hpp"
#include "pilempm/scenario/centrifuge/run_checks.hpp"
#include "pilempm/study/centrifuge_run.hpp"

namespace pilempm::cli {

using namespace scenario;

namespace {

struct CentrifugeFlags {
  std::string case_file;
  std::string out = "results/centrifuge";
  std::string python;
  bool quiet = false;
  bool no_plots = false;
  bool overwrite = false;
  std::string analysis;  ///< --analysis: "explicit", "quasi-static", or "" (the case file's)
  std::string restart;   ///< --restart: a checkpoint of a centrifuge run
};

// Whether the checkpoint lies in the run folder being written (DIR/mpm/checkpoint_*.h5): the
// run continues itself there, and the folder's files are kept.
bool restarts_in_its_own_folder(const CentrifugeFlags& flags) {
  if (flags.restart.empty()) return false;
  std::error_code out_error, checkpoint_error;
  const std::filesystem::path out = std::filesystem::weakly_canonical(flags.out, out_error);
  const std::filesystem::path checkpoint =
      std::filesystem::weakly_canonical(flags.restart, checkpoint_error);
  if (out_error || checkpoint_error) return false;
  const std::filesystem::path folder = out.has_filename() ? out : out.parent_path();
  return checkpoint.parent_path().parent_path() == folder;
}

std::string shown(double value, const char* format) {
  return shown_number(value, format);
}

// "checks: PASS" or a FAILED line per failed check; then ChecksFailed (exit status 4).
void report_checks(const std::vector<CentrifugeCheck>& checks, const std::string& summary) {
  const std::vector<CentrifugeCheck> failed = failed_checks(checks);
  if (failed.empty()) {
    fmt::print("checks: PASS ({} of the run's own checks; limits in docs/verification.md §8)\n",
               checks.size());
    return;
  }
  for (const CentrifugeCheck& c : failed) fmt::print("FAILED: {}\n", c.text());
  std::fflush(stdout);
  std::string names;
  for (const CentrifugeCheck& c : failed) names += (names.empty() ? "" : ", ") + c.name;
  throw ChecksFailed(
      fmt::format("the run failed {} of its own checks ({}); its results are kept "
                  "in {} and the files beside it",
                  failed.size(), names, summary));
}

void run_centrifuge_command(const CentrifugeFlags& flags) {
  const bool builtin = flags.case_file.empty();
  const std::string source = builtin ? std::string("built-in quick case") : flags.case_file;
  const std::string text =
      builtin ? std::string(quick_centrifuge_case_text()) : read_case_text(flags.case_file);
  const CentrifugeScenario scenario =
      read_centrifuge_case_text(text, source, analysis_option(flags.analysis));
  fmt::print("{}: \"{}\", {} analysis{}, phases {} -> {}/\n", source, scenario.title,
             to_string(scenario.analysis), flags.analysis.empty() ? "" : " (--analysis)",
             fmt::join(scenario_phase_names(scenario), ", "), flags.out);
  std::fflush(stdout);
  OutputFolderOptions folder;
  folder.overwrite = flags.overwrite;
  folder.resume = restarts_in_its_own_folder(flags);
  if (folder.resume && folder.overwrite)
    throw InputError("command line", 0, "--overwrite", "",
                     "not with --restart from a checkpoint in the output folder: it would "
                     "remove the checkpoint (the run's own files there are kept without it)");
  if (!flags.restart.empty()) {
    if (!std::filesystem::is_regular_file(flags.restart))
      throw InputError("command line", 0, "--restart", flags.restart, "no such checkpoint file");
    // Before the output folder is touched: a checkpoint that cannot continue the case costs
    // nothing written.
    check_centrifuge_restart(scenario, flags.restart);
  }
  take_output_folder(flags.out, folder);
  CentrifugeRunOptions options;
  options.restart = flags.restart;
  options.python = flags.python;
  options.plots = !flags.no_plots;
  options.progress_on_terminal = isatty(STDERR_FILENO) != 0;
  const CentrifugeSummary r =
      run_centrifuge(scenario, text, flags.out, flags.quiet ? nullptr : &std::cerr, options);
  fmt::print("head force at the end of installation: {} N (tip at {} D)\n",
             shown(r.installation_head_force, "{:.1f}"),
             shown(r.installation_tip_depth_D, "{:.2f}"));
  fmt::print("peak tip stress: {} MPa at {} D\n", shown(r.peak_tip_stress_MPa, "{:.2f}"),
             shown(r.peak_tip_stress_depth_D, "{:.2f}"));
  fmt::print("load-test capacity: {} N at {} mm\n", shown(r.capacity, "{:.1f}"),
             shown(r.load_test_displacement_mm, "{:.3g}"));
  fmt::print(
      "head-force scatter about a quadratic over a D of travel: {} % over the last D, at most {} % "
      "(from {} D of travel)\n",
      shown(100.0 * r.scatter_last_D, "{:.2f}"), shown(100.0 * r.largest_scatter, "{:.2f}"),
      shown(r.largest_scatter_from_D, "{:.3g}"));
  fmt::print("checks: K0 stress error {} %, equilibrium error {} %, kinetic / work {} %\n",
             shown(100.0 * r.initial_stress_error, "{:.2f}"),
             shown(100.0 * r.equilibrium_error, "{:.2f}"),
             shown(100.0 * r.max_kinetic_to_work, "{:.3f}"));
  fmt::print(
      "particles passed into the pile: {} (deepest centre {} cells inside its surface); smallest "
      "particle radius {} mm\n",
      r.particles_in_pile, shown(r.max_penetration_cells, "{:.2f}"),
      shown(r.min_radius_mm, "{:.3f}"));
  if (!r.plot_problem.empty())
    fmt::print(stderr, "warning: the figures were not drawn: {}\n", r.plot_problem);
  fmt::print("done: {} particles, {} steps in {:.1f} s; summary in {}/summary.md\n", r.particles,
             r.steps, r.wall_seconds, flags.out);
  report_checks(centrifuge_checks(r), flags.out + "/summary.md");
}

}  // namespace

void register_centrifuge_commands(CLI::App& app) {
  CLI::App* centrifuge =
      app.add_subcommand("centrifuge", "the centrifuge pile test (docs/centrifuge.md)");
  centrifuge->require_subcommand(1);

  auto flags = std::make_shared<CentrifugeFlags>();
  CLI::App* run = centrifuge->add_subcommand(
      "run",
      "run a centrifuge case: K0 stress, pile wished in place, jacked installation, relaxation "
      "and static load test; writes pile.csv, fields_*.csv/.vtu, summary.md/.json, PNG plots and "
      "the MPM output (mpm/)");
  run->add_option("case", flags->case_file,
                  "the centrifuge case file (TOML); none: the built-in quick case "
                  "(examples/centrifuge/quick.toml)")
      ->type_name("CASE.toml");
  run->add_option("--out", flags->out, "output folder")->capture_default_str()->type_name("DIR");
  run->add_option("--python", flags->python,
                  "Python interpreter with matplotlib for the plots (default: /usr/bin/python3, "
                  "then python3 on PATH)")
      ->type_name("PROGRAM");
  run->add_flag("--no-plots", flags->no_plots, "write figures.json but do not draw the PNGs");
  run->add_flag("--quiet", flags->quiet, "no progress lines on stderr");
  add_overwrite_flag(*run, flags->overwrite);
  add_analysis_option(*run, flags->analysis);
  run->add_option(
         "--restart", flags->restart,
         "continue from a checkpoint of a centrifuge run (DIR/mpm/checkpoint_NN_<phase>.h5) "
         "whose MPM case up to that phase is this case's (only the later phases may "
         "differ: MPM-4 continues MPM-3's installation); the outputs hold the whole run")
      ->type_name("FILE");
  run->callback([flags]() { run_centrifuge_command(*flags); });

  auto case_file = std::make_shared<std::string>();
  auto case_analysis = std::make_shared<std::string>();
  CLI::App* show = centrifuge->add_subcommand(
      "case", "print the MPM case (docs/mpm-case-files.md) a centrifuge case file becomes");
  show->add_option("case", *case_file, "the centrifuge case file; none: the built-in quick case")
      ->type_name("CASE.toml");
  add_analysis_option(*show, *case_analysis);
  show->callback([case_file, case_analysis]() {
    const bool builtin = case_file->empty();
    const std::string text =
        builtin ? std::string(quick_centrifuge_case_text()) : read_case_text(*case_file);
    const std::string source = builtin ? "built-in quick case" : *case_file;
    const CentrifugeScenario s =
        read_centrifuge_case_text(text, source, analysis_option(*case_analysis));
    fmt::print("{}", centrifuge_mpm_case_text(centrifuge_case(s, source)));
  });
}

}  // namespace pilempm::cli
