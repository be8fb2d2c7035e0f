#pragma once
// The calibration study of the Deltares report reproduced by one call (`pilempm study
// calibration --out DIR`): the element tests of examples/study_calibration.toml (built in) run
// into DIR/tests/, then for each item of the study (docs/study.md §2, §3, §5) a CSV with the units
// in the column names, the tables computed from the curves and from the analytical relations, a
// description of the figures (DIR/figures.json) drawn as PNG files by the plotting script
// (DIR/plot_figures.py, see plotting.hpp), and DIR/README.md with the tables, the figures and the
// initial void-ratio convention of every item. Each item is one file under study/calibration/
// and works on the results of the element tests in memory (study/calibration/item.hpp).
//
// The items, in order: oedometer curves (h_s = 4 and 2 GPa); drained triaxial curves (dense,
// loose, Deltares); cyclic oedometer with IGS 1-4 and without (initial stiffness, accumulated
// strain); the high-pressure triaxial table beside Bolton (1986); alpha against p after Herle &
// Gudehus (1999) with the stress-dependent alpha law; triaxial at 6 MPa for several alpha; the
// modified against the original set at 10 and 0.1 MPa; the stress-dependent alpha option against
// both sets.
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "pilempm/analytic/bolton.hpp"
#include "pilempm/analytic/herle_gudehus.hpp"
#include "pilempm/io/element_case.hpp"
#include "pilempm/study/oedometer_stiffness.hpp"
#include "pilempm/study/plotting.hpp"

namespace pilempm {

struct CalibrationStudyOptions {
  /// Every test with a quarter of its increments (for the test suite); every item is kept.
  bool quick = false;
  /// Run the plotting script; false writes the CSVs, figures.json and README.md only.
  bool plots = true;
  /// Python interpreter for the plots; "" = /usr/bin/python3, then python3 on PATH.
  std::string python;
};

/// One item of the study and what it wrote.
struct StudyItem {
  std::string key;    ///< short name, also the stem of its files ("oedometer", ...)
  std::string title;  ///< heading in README.md
  bool ok = true;
  std::string error;             ///< why it failed (a test of it failed, ...)
  std::string convention;        ///< the initial void-ratio convention(s) its tests used
  std::vector<std::string> csv;  ///< CSV files (names in the output folder)
  std::vector<std::string> png;  ///< figures (names in the output folder)
};

/// High-pressure triaxial: the model's peak beside Bolton's (p' = sigma3, as in the study).
struct HighPressureRow {
  std::string test;
  double sigma3 = 0.0;              ///< [Pa]
  double initial_void_ratio = 0.0;  ///< e at the start (e0 scaled by Bauer's law) [-]
  double peak_q = 0.0;              ///< [Pa]
  double axial_strain_at_peak = 0.0;
  double phi_peak_deg = 0.0, psi_peak_deg = 0.0;
  bool peak_at_end = false;  ///< q still rose at the end: no peak reached
  BoltonResult bolton{};     ///< Bolton (1986) at I_D and phi_c of the study, p' = sigma3
};

/// alpha(p) of Herle & Gudehus for one e0 and convention (original set).
struct AlphaPressureSeries {
  double e0 = 0.0;
  VoidRatioConvention convention = VoidRatioConvention::at_initial_stress;
  std::vector<AlphaPoint> points;
};

/// Cyclic oedometer: stiffness of one intergranular strain set, compared with no IGS.
struct CyclicStiffnessRow {
  std::string test, igs;
  CyclicOedometerStiffness stiffness{};
  double initial_secant_ratio = 0.0;   ///< initial secant modulus / the one without IGS
  double first_increment_ratio = 0.0;  ///< first-increment modulus / the one without IGS
};

/// Stress-dependent alpha against the set it should match at one cell pressure.
struct StressDependentRow {
  double sigma3 = 0.0;              ///< [Pa]
  double initial_void_ratio = 0.0;  ///< [-]
  double alpha_at_start = 0.0;      ///< the option's alpha at p = sigma3 [-]
  double phi_option_deg = 0.0, phi_original_deg = 0.0, phi_modified_deg = 0.0;
  std::string compared_with;    ///< "original" (0.1 MPa) or "modified" (10 MPa)
  double difference_deg = 0.0;  ///< option - compared set
};

struct CalibrationStudyReport {
  std::filesystem::path out_dir, tests_dir, readme, figures_json, plot_script;
  bool quick = false;
  std::vector<StudyItem> items;
  std::size_t tests_run = 0, tests_failed = 0;
  bool plots_requested = true;
  PlotOutcome plots;  ///< how the figures were drawn, or why not
  std::vector<HighPressureRow> high_pressure;
  std::vector<AlphaPressureSeries> alpha_pressure;
  std::vector<CyclicStiffnessRow> cyclic_stiffness;
  std::vector<StressDependentRow> stress_dependent;
  double seconds = 0.0;

  /// Every CSV and PNG the items wrote (names in the output folder).
  std::vector<std::string> csv_files() const;
  std::vector<std::string> png_files() const;
  std::size_t failed_items() const;
};

/// The study's case: examples/study_calibration.toml, compiled into the program.
std::string_view calibration_study_case_text();
ElementCaseFile calibration_study_case();
inline constexpr const char* kCalibrationStudyCaseName =
    "<built-in examples/study_calibration.toml>";

/// The names of the tests the study runs, in the order it runs them. The study finds its series
/// in the case by these names.
std::vector<std::string> calibration_study_test_names();

/// Divides the increments of every test by `divisor` (keeping at least 25 per oedometer segment
/// and 100 per triaxial or isotropic test): the quick run of the test suite.
void reduce_increments(ElementCaseFile& file, int divisor);

/// Runs the study into `out_dir` (created if needed). Lines for a person go to `progress`.
/// Throws Error when the folder cannot be written or a file cannot be written; a failed element
/// test or a missing plotting tool is reported in the result (and README.md), not thrown.
CalibrationStudyReport run_calibration_study(
    const std::filesystem::path& out_dir, const CalibrationStudyOptions& options,
    const std::function<void(const std::string&)>& progress = {});

}  // namespace pilempm
