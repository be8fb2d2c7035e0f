// `pilempm calibrate CASE.toml --out DIR`: fits the hypoplastic and intergranular-strain
// parameters to laboratory curves (docs/calibration.md). With --make-data it writes the case's
// data files from a known parameter set instead (the example's data and the checks are made so).
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "cli/commands.hpp"
#include "pilempm/calibration/fit.hpp"
#include "pilempm/io/calibration_case.hpp"
#include "pilempm/io/calibration_output.hpp"
#include "pilempm/io/element_output.hpp"
#include "pilempm/io/material_reader.hpp"
#include "pilempm/io/output/atomic_file.hpp"
#include "pilempm/study/plotting.hpp"

namespace pilempm::cli {

namespace {

namespace fs = std::filesystem;

struct CalibrateFlags {
  std::string case_file;
  std::string out;
  int threads = 0;
  std::string method;
  bool no_plots = false;
  bool overwrite = false;
  std::string python;
  // Synthetic data.
  std::string truth;
  std::string truth_igs;
  double noise = 0.01;
  unsigned seed = 1;
};

// A built-in set name, or FILE.toml with one hypoplastic [[material]] (e.g. a parameters.toml).
calibration::ParameterSet truth_set(const CalibrateFlags& f,
                                    const calibration::CalibrationProblem& problem) {
  calibration::ParameterSet truth;
  truth.igs = problem.base.igs;
  if (fs::exists(f.truth) && fs::is_regular_file(f.truth)) {
    const toml::table document = parse_toml_file(f.truth);
    TableReader root(document, f.truth, "");
    MaterialCatalog catalog;
    catalog.read(root);
    const std::vector<std::string> names = catalog.names();
    const MaterialSpec* m = catalog.find(names.front());
    if (m == nullptr || m->builtin || !m->is_hypoplastic())
      throw InputError(f.truth, 0, "material", "",
                       "missing: --make-data FILE needs a hypoplastic [[material]] in FILE");
    truth.hypoplastic = m->hypoplastic();
    if (m->hypoplastic_material().igs) truth.igs = m->hypoplastic_material().igs->parameters;
  } else {
    try {
      truth.hypoplastic = hypoplastic_set(f.truth);
    } catch (const InvalidValue& e) {
      throw InputError("command line", 0, "--make-data", f.truth,
                       std::string("neither a file nor a built-in set: ") + e.what());
    }
  }
  if (!f.truth_igs.empty()) truth.igs = named_igs(f.truth_igs).parameters;
  return truth;
}

void make_data(const CalibrateFlags& f) {
  CalibrationCase c = read_calibration_case(f.case_file, false);
  const calibration::ParameterSet truth = truth_set(f, c.problem);
  calibration::make_synthetic_data(c.problem, truth, f.noise, f.seed);
  for (std::size_t k = 0; k < c.problem.tests.size(); ++k) {
    const fs::path& file = c.data_files[k];
    if (file.has_parent_path()) fs::create_directories(file.parent_path());
    write_file_atomically(
        file, measured_curve_csv(
                  c.problem.tests[k],
                  fmt::format("synthetic data: pilempm calibrate {} --make-data {}{} --noise {} "
                              "--seed {}; Gaussian noise, standard deviation {} times each "
                              "quantity's range in the test",
                              f.case_file, f.truth,
                              f.truth_igs.empty() ? "" : " --truth-igs " + f.truth_igs, f.noise,
                              f.seed, f.noise)));
    fmt::print("wrote {}\n", file.string());
  }
}

void calibrate(const CalibrateFlags& f) {
  CalibrationCase c = read_calibration_case(f.case_file, true);
  if (f.threads > 0) c.problem.threads = f.threads;
  if (!f.method.empty()) c.problem.method = f.method;
  for (const std::string& w : c.warnings) fmt::print(stderr, "pilempm: warning: {}\n", w);
  OutputFolderOptions folder;
  folder.overwrite = f.overwrite;
  take_output_folder(f.out, folder);
  fmt::print("calibrate: {} test(s), {} free parameter(s), {} thread(s), method {}\n",
             c.problem.tests.size(), c.problem.free.size(), c.problem.threads, c.problem.method);
  const calibration::FitResult result =
      calibration::calibrate(c.problem, [](const calibration::FitProgress& p) {
        if (!p.message.empty()) {
          fmt::print("calibrate: {}: {} ({} element tests, {:.1f} s)\n", p.stage, p.message, p.runs,
                     p.seconds);
        } else {
          fmt::print(
              "calibrate: {} {}/{}: misfit {:.4g}, {} element tests, {:.1f} s, at most "
              "{:.0f} s left\n",
              p.stage, p.step, p.max_steps, p.misfit, p.runs, p.seconds, p.seconds_left);
        }
        std::fflush(stdout);
      });
  const fs::path figures = write_calibration_results(c, result, f.out);
  fmt::print("calibrate: {}\ncalibrate: misfit {:.4g} -> {:.4g}; {} element tests in {:.1f} s\n",
             result.termination, result.start_misfit, result.final_misfit, result.runs,
             result.seconds);
  for (const auto& s : result.sensitivity)
    if (!s.determined)
      fmt::print("calibrate: {} is not determined by the data ({})\n",
                 calibration::parameter_name(s.id), s.note);
  if (!f.no_plots) {
    const PlotOutcome plot =
        draw_figures(f.out / fs::path("plot_calibration.py"), figures, f.python);
    if (!plot.plotted)
      fmt::print(stderr,
                 "pilempm: warning: figures not drawn ({}); draw them later with "
                 "/usr/bin/python3 {}/plot_calibration.py {}\n",
                 plot.problem, f.out, figures.string());
  }
  fmt::print("calibrate: wrote {}/parameters.toml, report.md, history.csv\n", f.out);
}

}  // namespace

void register_calibrate_commands(CLI::App& app) {
  auto flags = std::make_shared<CalibrateFlags>();
  CLI::App* sub = app.add_subcommand(
      "calibrate",
      "fit the hypoplastic (and intergranular-strain) parameters to laboratory curves: "
      "pilempm calibrate CASE.toml --out DIR (docs/calibration.md)");
  sub->add_option("case", flags->case_file, "the calibration case file (TOML)")->required();
  sub->add_option("--out", flags->out, "output folder (required unless --make-data)");
  sub->add_option("--threads", flags->threads,
                  "threads running element tests (default: the case's, else 2)")
      ->check(CLI::Range(1, 256));
  sub->add_option("--method", flags->method, "ceres-lm (default) or nlopt-bobyqa")
      ->check(CLI::IsMember({"ceres-lm", "nlopt-bobyqa"}));
  sub->add_flag("--no-plots", flags->no_plots, "do not draw the PNG figures");
  add_overwrite_flag(*sub, flags->overwrite);
  sub->add_option("--python", flags->python,
                  "Python interpreter with matplotlib (default /usr/bin/python3, then python3)");
  sub->add_option("--make-data", flags->truth,
                  "instead of fitting, write each test's data file from this parameter set (a "
                  "built-in set or a TOML file with one hypoplastic [[material]]) with noise");
  sub->add_option("--truth-igs", flags->truth_igs,
                  "with --make-data: the IGS set of the data (default: the case's igs)");
  sub->add_option("--noise", flags->noise,
                  "with --make-data: Gaussian noise, standard deviation as a fraction of each "
                  "quantity's range in its test")
      ->check(sane_number() & CLI::Range(0.0, 1.0))
      ->capture_default_str();
  sub->add_option("--seed", flags->seed, "with --make-data: random seed")
      ->check(CLI::Range(0u, 4294967295u))
      ->capture_default_str();
  sub->callback([flags]() {
    if (!flags->truth.empty()) {
      make_data(*flags);
      return;
    }
    if (flags->out.empty())
      throw InputError("command line", 0, "--out", "", "missing: give the output folder");
    calibrate(*flags);
  });
}

}  // namespace pilempm::cli
