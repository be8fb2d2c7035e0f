// `pilempm study ...`: the studies reproduced by one command. `calibration` runs the
// calibration study of the Deltares report (element tests, analytical relations, the
// stress-dependent alpha option) and writes its CSVs, figures and README.md into a folder.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <CLI/CLI.hpp>

#include <cstdio>
#include <memory>
#include <string>

#include "cli/commands.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/study/calibration_study.hpp"

namespace pilempm::cli {

namespace {

struct CalibrationFlags {
  std::string out;
  bool quick = false;
  bool no_plots = false;
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
  calibration
      ->add_option("--python", flags->python,
                   "Python interpreter with matplotlib for the figures (default: "
                   "/usr/bin/python3, then python3 on PATH)")
      ->type_name("PATH");
  calibration->callback([flags]() { run_calibration(*flags); });
}

}  // namespace pilempm::cli
