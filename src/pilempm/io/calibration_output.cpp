#include "pilempm/io/calibration_output.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "pilempm/io/element_output.hpp"
#include "pilempm/io/output/atomic_file.hpp"
#include "pilempm/io/plot_calibration_script.hpp"  // generated from tools/plot/plot_calibration.py

namespace pilempm {

namespace fs = std::filesystem;
using namespace calibration;

namespace {

std::string value_text(double v) {
  return fmt::format("{:.6g}", v);
}

bool is_free(const CalibrationProblem& p, ParameterId id) {
  return std::any_of(p.free.begin(), p.free.end(),
                     [id](const FreeParameter& f) { return f.id == id; });
}

const FreeParameter* free_of(const CalibrationProblem& p, ParameterId id) {
  for (const FreeParameter& f : p.free)
    if (f.id == id) return &f;
  return nullptr;
}

}  // namespace

std::string parameters_toml(const CalibrationProblem& problem, const ParameterSet& s,
                            const std::string& comment) {
  std::string out = "# " + comment + "\n";
  out +=
      "# A [[material]] table: paste it into an element or centrifuge case file, or append the\n";
  out += "# case's tables to this file, and name the material \"" + problem.material_name + "\".\n";
  out += "[[material]]\n";
  out += fmt::format("name = \"{}\"\nmodel = \"hypoplastic\"\n", problem.material_name);
  for (ParameterId id : all_parameters()) {
    if (is_igs_parameter(id)) continue;
    out += fmt::format("{} = {}{}\n", parameter_name(id), value_text(get(s, id)),
                       is_free(problem, id) ? "  # fitted" : "");
  }
  if (s.igs.enabled())
    out += fmt::format("igs = {{ m_R = {}, m_T = {}, R = {}, beta_r = {}, chi = {} }}\n",
                       value_text(s.igs.m_R), value_text(s.igs.m_T), value_text(s.igs.R),
                       value_text(s.igs.beta_r), value_text(s.igs.chi));
  return out;
}

std::string history_csv(const CalibrationProblem& problem, const FitResult& result) {
  std::string out = "stage,step,element_test_runs,seconds,misfit";
  for (const FreeParameter& f : problem.free) out += fmt::format(",{}", parameter_name(f.id));
  out += "\n";
  for (const HistoryRow& row : result.history) {
    out += fmt::format("{},{},{},{:.3f},{:.8g}", row.stage, row.step, row.runs, row.seconds,
                       row.misfit);
    for (const FreeParameter& f : problem.free)
      out += fmt::format(",{:.8g}", get(row.parameters, f.id));
    out += "\n";
  }
  return out;
}

std::string calibration_report(const CalibrationCase& c, const FitResult& r) {
  const CalibrationProblem& p = c.problem;
  std::string out = fmt::format("# Calibration: {}\n\n", c.title.empty() ? p.source : c.title);
  out += fmt::format(
      "Case `{}`; starting set `{}`{}; {} test(s), {} free parameter(s); method {}.\n\n", p.source,
      p.base_set, p.uses_igs() ? fmt::format(" with intergranular strain `{}`", p.igs_base) : "",
      p.tests.size(), p.free.size(), r.method);
  out += fmt::format("Outcome: {}.\n\n", r.termination);
  out += fmt::format(
      "Misfit (sum of squared weighted residuals, each quantity normalised by its measured "
      "range): start {:.4g}, fitted {:.4g}.\n\n",
      r.start_misfit, r.final_misfit);
  out += fmt::format(
      "Time {:.1f} s with {} thread(s): {} element-test runs (start {} runs, {:.1f} s; "
      "refinement {} runs, {:.1f} s; sensitivity {} runs, {:.1f} s).\n\n",
      r.seconds, p.threads, r.runs, r.runs_start, r.seconds_start, r.runs_refine, r.seconds_refine,
      r.runs_sensitivity, r.seconds_sensitivity);
  for (const std::string& w : c.warnings) out += "Warning (data): " + w + "\n\n";
  for (const std::string& w : r.warnings) out += "Warning (fit): " + w + "\n\n";

  out += "## Parameters\n\n";
  out +=
      "| parameter | start set | physics start | fitted | lower | upper | how the start was set "
      "|\n";
  out += "|---|---:|---:|---:|---:|---:|---|\n";
  for (ParameterId id : all_parameters()) {
    if (is_igs_parameter(id) && !p.uses_igs()) continue;
    const FreeParameter* f = free_of(p, id);
    std::string how = f ? "starting set" : "fixed";
    for (const StartNote& n : r.start_notes)
      if (n.id == id) how = n.how;
    if (f && f->start) how = "start value of the case";
    out += fmt::format("| {} | {} | {} | {} | {} | {} | {} |\n", parameter_name(id),
                       value_text(get(p.base, id)), value_text(get(r.start, id)),
                       value_text(get(r.fitted, id)), f ? value_text(f->lower) : "",
                       f ? value_text(f->upper) : "", how);
  }

  out += "\n## Residuals per test and quantity\n\n";
  out +=
      "Normalised RMS = RMS(fitted - measured) / (range of the measured values); with data "
      "whose noise has standard deviation s times that range, a fit to the noise gives about "
      "s.\n\n";
  out +=
      "| test | type | quantity | points | weight | normalised RMS | RMS [unit of the column] |\n";
  out += "|---|---|---|---:|---:|---:|---:|\n";
  for (const QuantityFit& q : r.quantities) {
    const LabTest& t = p.tests[q.test];
    const MeasuredQuantity& m = t.quantities[q.quantity];
    out += fmt::format("| {} | {} | {} | {} | {} | {:.4f} | {:.4g} |\n", t.name,
                       test_type_name(t.test), m.column, m.values.size(),
                       value_text(t.weight * m.weight), q.rms, q.rms * m.scale());
  }

  out += "\n## Sensitivity\n\n";
  out +=
      "From the Jacobian at the fitted set (forward differences, 0.1 % of each bound range). "
      "`misfit rise` is the relative rise of the misfit when the parameter alone moves by "
      "10 % of its bound range; the standard error is the Gauss-Newton estimate "
      "sqrt(s^2 (J^T J)^-1) with s^2 the misfit per degree of freedom. A parameter is "
      "reported undetermined when its standard error exceeds 5 % of its bound range.\n\n";
  out +=
      "| parameter | fitted | misfit rise (10 % of range) | standard error | error / range | "
      "determined | note |\n";
  out += "|---|---:|---:|---:|---:|---|---|\n";
  for (const Sensitivity& s : r.sensitivity)
    out += fmt::format("| {} | {} | {:.3g} | {:.3g} | {:.3f} | {} | {} |\n", parameter_name(s.id),
                       value_text(get(r.fitted, s.id)), s.misfit_rise_10pct, s.standard_error,
                       s.standard_error_fraction, s.determined ? "yes" : "**no**", s.note);
  if (!r.correlations.empty()) {
    out +=
        "\nStrongly correlated pairs (|correlation| > 0.9): the data fix a combination of "
        "them rather than each one:\n\n";
    for (const std::string& s : r.correlations) out += "- " + s + "\n";
  }
  out += "\n## Figures\n\n";
  for (const LabTest& t : p.tests) out += fmt::format("![{0}]({0}.png)\n\n", t.name);
  out +=
      "Files: `parameters.toml` (the fitted [[material]]), `history.csv` (the refinement), "
      "`NAME.data.csv` and `NAME.fit.csv` per test (measured and fitted curves), "
      "`figures.json` and `plot_calibration.py` (redraw: `/usr/bin/python3 "
      "plot_calibration.py figures.json`).\n";
  return out;
}

std::string_view plot_calibration_script() {
  return {reinterpret_cast<const char*>(generated::kPlotCalibrationScript),
          sizeof(generated::kPlotCalibrationScript)};
}

fs::path write_calibration_results(const CalibrationCase& c, const FitResult& result,
                                   const fs::path& directory) {
  const CalibrationProblem& p = c.problem;
  prepare_output_directory(directory);
  write_file_atomically(directory / "parameters.toml",
                        parameters_toml(p, result.fitted,
                                        fmt::format("pilempm calibrate {}: fitted misfit {:.4g}",
                                                    p.source, result.final_misfit)));
  write_file_atomically(directory / "history.csv", history_csv(p, result));
  write_file_atomically(directory / "report.md", calibration_report(c, result));
  write_file_atomically(directory / "case.toml", c.text);
  const ModelPtr model = make_hypoplastic(result.fitted, p.integrator);
  std::string figures = "{\"tests\": [";
  for (std::size_t k = 0; k < p.tests.size(); ++k) {
    const LabTest& t = p.tests[k];
    write_file_atomically(directory / (t.name + ".data.csv"),
                          measured_curve_csv(t, "measured curve of " + t.data_source));
    std::string fit_file;
    try {
      write_file_atomically(directory / (t.name + ".fit.csv"),
                            curve_csv(run_lab_test(t, model).curve));
      fit_file = t.name + ".fit.csv";
    } catch (const Error&) {
      // The fitted model fails on this test: the figure shows the data only.
    }
    std::string quantities;
    for (const MeasuredQuantity& q : t.quantities)
      quantities += fmt::format("{}\"{}\"", quantities.empty() ? "" : ", ", q.column);
    figures += fmt::format(
        "{}\n  {{\"name\": \"{}\", \"type\": \"{}\", \"x\": \"{}\", \"y\": [{}], \"data\": "
        "\"{}.data.csv\", \"fit\": \"{}\", \"png\": \"{}.png\"}}",
        k ? "," : "", t.name, test_type_name(t.test), t.abscissa_column, quantities, t.name,
        fit_file, t.name);
  }
  figures += "\n]}\n";
  const fs::path json = directory / "figures.json";
  write_file_atomically(json, figures);
  write_file_atomically(directory / "plot_calibration.py", plot_calibration_script());
  return json;
}

}  // namespace pilempm
