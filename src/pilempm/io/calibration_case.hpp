#pragma once
// Calibration case files (format: docs/calibration.md): the laboratory tests, each an element
// test with `data = "FILE.csv"` (a measured curve with the column names and units of pilempm's
// own curve CSVs), the parameters to fit with their bounds, and the settings of the fit. Read
// into a calibration::CalibrationProblem; every error names file, line, key or column.
#include <filesystem>
#include <string>
#include <vector>

#include "pilempm/calibration/calibration_problem.hpp"
#include "pilempm/core/error.hpp"

namespace pilempm {

struct CalibrationCase {
  calibration::CalibrationProblem problem;
  std::string title;
  std::string text;                               ///< the TOML text that was read
  std::vector<std::filesystem::path> data_files;  ///< per test, resolved against the case's folder
  std::vector<std::string> warnings;              ///< data problems the fit can live with
};

/// Reads a case file and, when `read_data`, each test's CSV (checked: columns, units, NaN,
/// monotonic loading, point counts). Without data the tests have no measured points (for
/// `pilempm calibrate synthesize`). Throws InputError naming file, line and key or column.
CalibrationCase read_calibration_case(const std::filesystem::path& path, bool read_data = true);
/// The same for TOML text; data paths are resolved against `directory`.
CalibrationCase parse_calibration_case(std::string text, const std::string& source_name,
                                       const std::filesystem::path& directory,
                                       bool read_data = true);

/// Reads one measured curve into `test` (its abscissa_column and the columns of its quantities
/// must be set). Appends warnings. Throws InputError naming the file, the line and the column.
void read_measured_curve(const std::filesystem::path& file, calibration::LabTest& test,
                         std::vector<std::string>& warnings);

/// A measured curve as CSV (the abscissa and the quantities, pilempm's column names).
std::string measured_curve_csv(const calibration::LabTest& test, const std::string& comment);

}  // namespace pilempm
