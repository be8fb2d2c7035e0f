#pragma once
// What `pilempm calibrate` writes (docs/calibration.md): parameters.toml (a [[material]] table
// that element and centrifuge case files accept unchanged), report.md, history.csv, per test the
// measured curve (NAME.data.csv) and the fitted model's curve (NAME.fit.csv), and figures.json
// for tools/plot/plot_calibration.py, which draws NAME.png.
#include <filesystem>
#include <string>
#include <string_view>

#include "pilempm/calibration/fit.hpp"
#include "pilempm/io/calibration_case.hpp"

namespace pilempm {

/// The fitted set as a [[material]] table (hypoplastic, with its igs inline table when the
/// intergranular strain is on).
std::string parameters_toml(const calibration::CalibrationProblem& problem,
                            const calibration::ParameterSet& fitted, const std::string& comment);

/// The refinement history: stage, step, element-test runs, seconds, misfit, the free parameters.
std::string history_csv(const calibration::CalibrationProblem& problem,
                        const calibration::FitResult& result);

/// The report (Markdown).
std::string calibration_report(const CalibrationCase& c, const calibration::FitResult& result);

/// Writes everything into `directory` (created if needed). Returns the figures.json path.
std::filesystem::path write_calibration_results(const CalibrationCase& c,
                                                const calibration::FitResult& result,
                                                const std::filesystem::path& directory);

/// The text of tools/plot/plot_calibration.py (built in).
std::string_view plot_calibration_script();

}  // namespace pilempm
