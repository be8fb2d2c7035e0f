// `pilempm study ...`: the studies reproduced by one command. `calibration` runs the
// calibration study of the Deltares report (element tests, analytical relations, the
// stress-dependent alpha option) and writes its CSVs, figures and README.md into a folder;
// `centrifuge` runs the centrifuge cases of examples/centrifuge/ and compares them.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/study/calibration_study.hpp"
#include "pilempm/study/centrifuge_study.hpp"

namespace pilempm::cli {

namespace {

struct CalibrationFlags {
  std::string out;
  bool quick = false;
  bool no_plots = false;
  bool overwrite = false;
  std::string python;
};

void run_calibration(const CalibrationFlags& flags) {
  if (flags.out.empty())
    throw InputError("command line", 0, "--out", "", "missing: the folder to write the study into");
  CalibrationStudyOptions options;
  options.quick = flags.quick;
  options.plots = !flags.no_plots;
  options.python = flags.python;
  fmt::print("pilempm study calibration{} -> {}/\n", flags.quick ? " --quick" : "", flags.out);
  std::fflush(stdout);
  OutputFolderOptions folder;
  folder.overwrite = flags.overwrite;
  take_output_folder(flags.out, folder);
  const CalibrationStudyReport report =
      run_calibration_study(flags.out, options, [](const std::string& line) {
        fmt::print("{}\n", line);
        std::fflush(stdout);
      });
  fmt::print("\n{} items, {} CSV files, {} figures{} in {}/ ({:.1f} s); summary: {}\n",
             report.items.size(), report.csv_files().size(), report.png_files().size(),
             report.plots.plotted ? "" : " (described in figures.json, not drawn)",
             report.out_dir.string(), report.seconds, report.readme.string());
  std::fflush(stdout);
  if (report.tests_failed > 0 || report.failed_items() > 0)
    throw Error(fmt::format("{} of {} element tests failed, {} of {} items incomplete (see {})",
                            report.tests_failed, report.tests_run, report.failed_items(),
                            report.items.size(), report.readme.string()));
  if (!report.plots.plotted) {
    if (report.plots.python.empty() && options.plots) {
      // No usable interpreter: the results are complete without the PNG files.
      fmt::print(stderr,
                 "pilempm: warning: the figures were not drawn: {}{}. Everything else is "
                 "written; to draw the PNG files later (Debian: apt-get install "
                 "python3-matplotlib): /usr/bin/python3 {} {}\n",
                 report.plots.problem,
                 report.plots.tried.empty()
                     ? std::string()
                     : fmt::format(" (tried: {})", fmt::join(report.plots.tried, "; ")),
                 report.plot_script.string(), report.figures_json.string());
    } else if (options.plots) {
      throw Error(fmt::format("drawing the figures failed: {} (see the output above)",
                              report.plots.problem));
    }
  }
}

struct CentrifugeStudyFlags {
  std::string out;
  std::string cases = "examples/centrifuge";
  std::vector<std::string> groups;
  bool resume = false;
  bool report_only = false;
  bool no_plots = false;
  bool quiet = false;
  bool overwrite = false;
  std::string python;
};

void run_centrifuge_study_command(const CentrifugeStudyFlags& flags) {
  CentrifugeStudyOptions options;
  options.cases_dir = flags.cases;
  options.groups = flags.groups;
  options.resume = flags.resume;
  options.report_only = flags.report_only;
  options.plots = !flags.no_plots;
  options.python = flags.python;
  fmt::print(
      "pilempm study centrifuge: cases from {}/, groups {} -> {}/\n", flags.cases,
      flags.groups.empty() ? std::string("all") : fmt::format("{}", fmt::join(flags.groups, ", ")),
      flags.out);
  std::fflush(stdout);
  OutputFolderOptions folder;
  folder.overwrite = flags.overwrite;
  folder.resume = flags.resume || flags.report_only;  // the study's own earlier runs
  if (folder.resume && folder.overwrite)
    throw InputError("command line", 0, "--overwrite", "",
                     "not with --resume or --report-only, which use the runs in the folder");
  take_output_folder(flags.out, folder);
  const std::vector<CentrifugeStudyFailure> failed =
      run_centrifuge_study(options, flags.out, flags.quiet ? nullptr : &std::cerr);
  fmt::print("done: the comparison is in {}/README.md\n", flags.out);
  if (failed.empty()) return;
  std::string files;
  for (const CentrifugeStudyFailure& f : failed) {
    for (const std::string& check : f.checks) fmt::print("FAILED: {}: {}\n", f.file, check);
    files += (files.empty() ? "" : ", ") + f.file;
  }
  std::fflush(stdout);
  throw ChecksFailed(fmt::format(
      "{} run{} of the study failed {} own checks ({}); the results are kept in {}/ and marked "
      "FAILED in {}/README.md",
      failed.size(), failed.size() == 1 ? "" : "s", failed.size() == 1 ? "its" : "their", files,
      flags.out, flags.out));
}

}  // namespace

void register_study_commands(CLI::App& app) {
  CLI::App* study =
      app.add_subcommand("study", "the studies of the Deltares report, each by one command");
  study->require_subcommand(1);
  CLI::App* calibration = study->add_subcommand(
      "calibration",
      "the calibration study: oedometer, cyclic oedometer, drained and high-pressure triaxial, "
      "Bolton, alpha after Herle & Gudehus, alpha sensitivity, modified vs original set, "
      "stress-dependent alpha; writes per item a CSV and a PNG, and README.md");
  auto flags = std::make_shared<CalibrationFlags>();
  calibration->add_option("--out", flags->out, "output folder (created if needed)")
      ->required()
      ->type_name("DIR");
  calibration->add_flag("--quick", flags->quick,
                        "a quarter of the increments in every test (every item is kept)");
  calibration->add_flag("--no-plots", flags->no_plots,
                        "write the CSVs, figures.json and README.md, but draw no PNG files");
  add_overwrite_flag(*calibration, flags->overwrite);
  calibration
      ->add_option("--python", flags->python,
                   "Python interpreter with matplotlib for the figures (default: "
                   "/usr/bin/python3, then python3 on PATH)")
      ->type_name("PATH");
  calibration->callback([flags]() { run_calibration(*flags); });

  auto centrifuge_flags = std::make_shared<CentrifugeStudyFlags>();
  CLI::App* centrifuge = study->add_subcommand(
      "centrifuge",
      "the centrifuge study (docs/study.md §4): installation for both densities and parameter "
      "sets, the "
      "load tests MPM-1..4, the IGS study, the parametric study and stress-dependent alpha; each "
      "case into DIR/<case>/, the comparisons and README.md into DIR (hours on 2 cores: see "
      "docs/centrifuge.md)");
  centrifuge->add_option("--out", centrifuge_flags->out, "output folder (created if needed)")
      ->required()
      ->type_name("DIR");
  centrifuge->add_option("--cases", centrifuge_flags->cases, "the folder of the case files")
      ->capture_default_str()
      ->type_name("DIR");
  std::vector<std::string> group_names;
  for (const CentrifugeStudyGroup& g : centrifuge_study_groups()) group_names.push_back(g.name);
  centrifuge
      ->add_option("--groups", centrifuge_flags->groups,
                   fmt::format("run only these groups ({})", fmt::join(group_names, ", ")))
      ->delimiter(',')
      ->check(CLI::IsMember(group_names))
      ->type_name("GROUP,...");
  centrifuge->add_flag("--resume", centrifuge_flags->resume,
                       "keep the runs of an earlier call whose summary.csv exists");
  centrifuge->add_flag("--report-only", centrifuge_flags->report_only,
                       "run nothing: write README.md and the figures of the runs that exist "
                       "(a group is drawn when all its runs exist)");
  centrifuge->add_flag("--no-plots", centrifuge_flags->no_plots, "draw no PNG files");
  centrifuge->add_flag("--quiet", centrifuge_flags->quiet, "no progress lines on stderr");
  add_overwrite_flag(*centrifuge, centrifuge_flags->overwrite);
  centrifuge
      ->add_option("--python", centrifuge_flags->python,
                   "Python interpreter with matplotlib for the figures")
      ->type_name("PATH");
  centrifuge->callback([centrifuge_flags]() { run_centrifuge_study_command(*centrifuge_flags); });
}

}  // namespace pilempm::cli
