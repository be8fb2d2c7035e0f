// `pilempm study ...`: the studies reproduced by one command. `calibration` runs the
// calibration study of the Deltares report (element tests, analytical relations, the
// stress-dependent alpha option) and writes its CSVs, figures and README.md into a folder;
// `centrifuge` runs the centrifuge cases of examples/centrifuge/ (one after the other, --jobs N at
// once as child processes, or written as a command list for GNU parallel or Slurm) and compares
// them.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/study/calibration_study.hpp"
#include "pilempm/study/centrifuge_study.hpp"
#include "pilempm/study/process_pool.hpp"

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
  int jobs = 1;
  bool jobs_given = false;
  std::string write_commands;
  std::string analysis;        ///< --analysis, or "" (each case file's)
  std::string reference_data;  ///< --reference-data, or ""
};

// The pilempm program that runs: the child runs of the study start it again.
std::filesystem::path this_program() {
  std::error_code ec;
  const std::filesystem::path path = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec)
    throw Error(
        fmt::format("cannot find the pilempm program for the study's runs "
                    "(/proc/self/exe: {})",
                    ec.message()));
  return path;
}

// --jobs, --write-commands and --report-only each say how the runs happen: at most one of them.
void check_how_to_run(const CentrifugeStudyFlags& flags) {
  if (flags.jobs_given && flags.report_only)
    throw InputError("command line", 0, "--jobs", std::to_string(flags.jobs),
                     "not with --report-only, which runs nothing");
  if (!flags.write_commands.empty() && flags.report_only)
    throw InputError("command line", 0, "--write-commands", flags.write_commands,
                     "not with --report-only: write the commands first, run them, then "
                     "--report-only gathers their folders");
  if (!flags.write_commands.empty() && !flags.reference_data.empty())
    throw InputError("command line", 0, "--reference-data", flags.reference_data,
                     "not with --write-commands, which runs nothing: run the commands, then "
                     "--report-only --reference-data DIR gathers the finished runs");
  if (!flags.reference_data.empty() && std::filesystem::exists(flags.reference_data) &&
      !std::filesystem::is_directory(flags.reference_data))
    throw InputError("command line", 0, "--reference-data", flags.reference_data,
                     "a folder (created if needed), not a file");
  if (!flags.reference_data.empty()) {
    // The set replaces what it wrote before: it must not share a folder with the study's runs.
    const auto inside = [](const std::filesystem::path& a, const std::filesystem::path& b) {
      const std::filesystem::path relative = a.lexically_relative(b);
      return !relative.empty() && *relative.begin() != "..";
    };
    const std::filesystem::path data = std::filesystem::weakly_canonical(flags.reference_data);
    const std::filesystem::path out = std::filesystem::weakly_canonical(flags.out);
    if (inside(data, out) || inside(out, data))
      throw InputError("command line", 0, "--reference-data", flags.reference_data,
                       fmt::format("a folder apart from the study's --out {} (neither it, nor "
                                   "inside it, nor above it)",
                                   flags.out));
  }
  if (!flags.write_commands.empty() && flags.jobs_given)
    throw InputError("command line", 0, "--jobs", std::to_string(flags.jobs),
                     "not with --write-commands, which runs nothing (GNU parallel's -j says how "
                     "many of the commands run at once)");
}

void write_centrifuge_study_commands_command(const CentrifugeStudyOptions& options,
                                             const CentrifugeStudyFlags& flags) {
  const std::size_t lines =
      write_centrifuge_study_commands(options, flags.out, flags.write_commands);
  const std::string groups = flags.groups.empty()
                                 ? std::string()
                                 : fmt::format(" --groups {}", fmt::join(flags.groups, ","));
  fmt::print(
      "wrote {} command{} (one run a line; MPM-4 on MPM-3's) to {}; their folders go to {}/, their "
      "output to "
      "{}/logs/.\nRun them, e.g. `parallel -j 4 < {}` (GNU parallel; over ssh hosts with "
      "--sshloginfile) or as a Slurm job array (`sed -n \"${{SLURM_ARRAY_TASK_ID}}p\" {} | "
      "bash`), then gather them:\n  pilempm study centrifuge --out {} --cases {}{}{} "
      "--report-only\n",
      lines, lines == 1 ? "" : "s", flags.write_commands, flags.out, flags.out,
      shell_word(flags.write_commands), shell_word(flags.write_commands), shell_word(flags.out),
      shell_word(flags.cases), groups,
      flags.analysis.empty() ? std::string() : " --analysis " + flags.analysis);
}

void run_centrifuge_study_command(const CentrifugeStudyFlags& flags) {
  check_how_to_run(flags);
  CentrifugeStudyOptions options;
  options.cases_dir = flags.cases;
  options.groups = flags.groups;
  options.resume = flags.resume;
  options.report_only = flags.report_only;
  options.plots = !flags.no_plots;
  options.python = flags.python;
  options.analysis = analysis_option(flags.analysis);
  options.jobs = flags.jobs;
  options.reference_data = flags.reference_data;
  if (flags.jobs > 1 || !flags.write_commands.empty()) options.program = this_program();
  fmt::print(
      "pilempm study centrifuge: cases from {}/, groups {}{} -> {}/\n", flags.cases,
      flags.groups.empty() ? std::string("all") : fmt::format("{}", fmt::join(flags.groups, ", ")),
      flags.analysis.empty() ? std::string() : ", every run " + flags.analysis, flags.out);
  std::fflush(stdout);
  OutputFolderOptions folder;
  folder.overwrite = flags.overwrite;
  folder.resume = flags.resume || flags.report_only;  // the study's own earlier runs
  if (folder.resume && folder.overwrite)
    throw InputError("command line", 0, "--overwrite", "",
                     "not with --resume or --report-only, which use the runs in the folder");
  take_output_folder(flags.out, folder);
  if (!flags.write_commands.empty()) {
    write_centrifuge_study_commands_command(options, flags);
    return;
  }
  const std::vector<CentrifugeStudyFailure> failed =
      run_centrifuge_study(options, flags.out, flags.quiet ? nullptr : &std::cerr);
  fmt::print("done: the comparison is in {}/README.md\n", flags.out);
  if (failed.empty()) return;
  std::string files, unfinished;
  std::size_t runs_unfinished = 0;
  for (const CentrifugeStudyFailure& f : failed) {
    for (const std::string& check : f.checks) fmt::print("FAILED: {}: {}\n", f.file, check);
    if (!f.finished()) {
      fmt::print("FAILED: {}: did not finish: {}; its log: {}\n", f.file, f.ended, f.log.string());
      unfinished += fmt::format("{}{} ({}, log {})", unfinished.empty() ? "" : ", ", f.file,
                                f.ended, f.log.string());
      ++runs_unfinished;
    } else {
      files += (files.empty() ? "" : ", ") + f.file;
    }
  }
  std::fflush(stdout);
  if (runs_unfinished > 0)
    throw Error(fmt::format(
        "{} run{} of the study did not finish: {}; the other runs finished and {}/README.md "
        "lists them all (rerun with --resume to run only what is missing)",
        runs_unfinished, runs_unfinished == 1 ? "" : "s", unfinished, flags.out));
  throw ChecksFailed(fmt::format(
      "{} run{} of the study failed {} own checks ({}); the results are kept in {}/ and marked "
      "FAILED in {}/README.md",
      failed.size(), failed.size() == 1 ? "" : "s", failed.size() == 1 ? "its" : "their", files,
      flags.out, flags.out));
}

constexpr int kMinJobs = 1;
constexpr int kMaxJobs = 1024;

// --jobs: a whole number from kMinJobs to kMaxJobs; the message names the flag and the range.
CLI::Validator jobs_range() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const std::string shown = message_text(text);
        std::size_t used = 0;
        long value = 0;
        try {
          value = std::stol(text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used != text.size() || used == 0 || value < kMinJobs || value > kMaxJobs)
          return fmt::format(
              "the number of runs at once must be a whole number from {} to {}, not {}", kMinJobs,
              kMaxJobs, shown);
        return {};
      },
      "N");
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
                       "(a group's figures draw its runs that exist)");
  CLI::Option* jobs = centrifuge->add_option(
      "--jobs", centrifuge_flags->jobs,
      fmt::format("runs at once, each a child process on one thread (default 1: one after the "
                  "other in this process, on the cores; {} to {})",
                  kMinJobs, kMaxJobs));
  jobs->check(jobs_range())->type_name("N");
  centrifuge
      ->add_option("--write-commands", centrifuge_flags->write_commands,
                   "run nothing: write the runs as shell commands, one a line, into FILE for GNU "
                   "parallel or a Slurm job array; then --report-only gathers them "
                   "(docs/centrifuge.md)")
      ->type_name("FILE");
  centrifuge
      ->add_option("--reference-data", centrifuge_flags->reference_data,
                   "after the report, write the chosen groups' finished runs as a reference data "
                   "set into DIR: each case file, its curves of force against travel as CSV, and "
                   "README.md (docs/data/README.md; the set written there before is replaced)")
      ->type_name("DIR");
  centrifuge->add_flag("--no-plots", centrifuge_flags->no_plots, "draw no PNG files");
  centrifuge->add_flag("--quiet", centrifuge_flags->quiet, "no progress lines on stderr");
  add_overwrite_flag(*centrifuge, centrifuge_flags->overwrite);
  add_analysis_option(*centrifuge, centrifuge_flags->analysis);
  centrifuge
      ->add_option("--python", centrifuge_flags->python,
                   "Python interpreter with matplotlib for the figures")
      ->type_name("PATH");
  centrifuge->callback([centrifuge_flags, jobs]() {
    centrifuge_flags->jobs_given = jobs->count() > 0;
    run_centrifuge_study_command(*centrifuge_flags);
  });
}

}  // namespace pilempm::cli
