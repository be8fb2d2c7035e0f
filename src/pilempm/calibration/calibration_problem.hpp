#pragma once
// Fitting the hypoplastic and intergranular-strain parameters to laboratory curves
// (docs/calibration.md). A CalibrationProblem is a list of laboratory tests, each an element test
// of element_tests.hpp with its measured curve, and the parameters to fit with their bounds. The
// misfit of a parameter set is the vector of weighted, normalised differences between the curve
// pilempm's element-test driver computes and the measured one, at the measured points.
//
// Units: measured curves are in the units of pilempm's own curve CSVs (strains in per cent,
// stresses in kPa, compression positive); parameters in the units of the case files (h_s in MPa).
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/constitutive/hypoplastic/hypoplastic_parameters.hpp"
#include "pilempm/element/element_tests.hpp"

namespace pilempm::calibration {

/// The parameters a calibration may fit: the eight of von Wolffersdorff's model and the five of
/// the intergranular strain.
enum class ParameterId {
  phi_c_deg,
  h_s_MPa,
  n,
  e_d0,
  e_c0,
  e_i0,
  alpha,
  beta,
  m_R,
  m_T,
  R,
  beta_r,
  chi
};
inline constexpr int kParameterCount = 13;

/// The case-file name of a parameter ("phi_c_deg", "h_s_MPa", ..., "m_R", "R", ...).
std::string_view parameter_name(ParameterId id);
/// All ids in the order above.
const std::array<ParameterId, kParameterCount>& all_parameters();
/// The id of a case-file name (nullopt when unknown).
std::optional<ParameterId> parameter_from_name(std::string_view name);
/// Whether the parameter belongs to the intergranular strain.
bool is_igs_parameter(ParameterId id);

/// A complete parameter set of the model (SI inside).
struct ParameterSet {
  HypoplasticParameters hypoplastic{};
  IntergranularStrainParameters igs{};  ///< R = 0: no intergranular strain
};

/// A parameter's value in case-file units (h_s in MPa).
double get(const ParameterSet& set, ParameterId id);
void set(ParameterSet& set, ParameterId id, double value);

/// One free parameter: its bounds (case-file units) and whether it is searched on a log scale
/// (h_s and R, positive and spanning decades).
struct FreeParameter {
  ParameterId id;
  double lower = 0.0;
  double upper = 0.0;
  std::optional<double> start;  ///< a start value given by the user (skips the physics start)
  bool log_scale() const { return id == ParameterId::h_s_MPa || id == ParameterId::R; }
  /// Value of a normalised coordinate u in [0, 1] and back.
  double value(double u) const;
  double coordinate(double value) const;
};

/// A measured quantity of one test: a column of its CSV, the values at the measured points.
struct MeasuredQuantity {
  std::string column;  ///< a curve column, e.g. "q_kPa", "void_ratio"
  std::vector<double> values;
  double weight = 1.0;
  /// Normalising scale: the range of the measured values (or a floor for a flat curve).
  double scale() const;
};

/// One laboratory test: the element test that reproduces it and its measured curve.
struct LabTest {
  std::string name;
  ElementTest test;
  InitialCondition initial;
  double weight = 1.0;
  std::string abscissa_column;   ///< the controlled quantity: axial strain, sigma_a or p
  std::vector<double> abscissa;  ///< its measured values, in the CSV's units
  std::vector<MeasuredQuantity> quantities;
  std::string data_source;  ///< the CSV file
};

/// The controlled column of a test type: "axial_strain_pct" (triaxial, undrained triaxial),
/// "sigma_a_kPa" (oedometer), "p_kPa" (isotropic); "" for strain paths (not calibratable).
std::string abscissa_column_of(const ElementTest& test);
/// The quantities fitted by default: triaxial q and volumetric strain, undrained q and p,
/// oedometer and isotropic the void ratio.
std::vector<std::string> default_quantities_of(const ElementTest& test);

/// The curve columns a measured CSV may hold, in the units of pilempm's curve CSVs.
const std::vector<std::string>& curve_quantity_columns();
/// The value of a curve column at a curve point (throws Error for an unknown column).
double curve_value(const CurvePoint& point, std::string_view column);

/// The whole problem.
struct CalibrationProblem {
  std::string material_name = "calibrated";
  std::string base_set = "original";
  std::string igs_base = "none";  ///< named IGS set the intergranular parameters start from
  ParameterSet base;              ///< the starting set (base set with fixed values applied)
  std::vector<FreeParameter> free;
  std::vector<LabTest> tests;
  IntegratorSettings integrator{};
  bool physics_start = true;
  int max_iterations = 40;
  int threads = 2;
  std::string method = "ceres-lm";  ///< or "nlopt-bobyqa"
  std::string source;               ///< the case file

  bool uses_igs() const { return base.igs.enabled(); }
};

/// The model of a parameter set (throws InvalidValue for an impossible set).
ModelPtr make_hypoplastic(const ParameterSet& set, const IntegratorSettings& integrator);

/// The parameter set at normalised coordinates `u` (one per free parameter) over `base`.
ParameterSet parameters_at(const CalibrationProblem& problem, const std::vector<double>& u);
/// The normalised coordinates of a set's free parameters (clamped to [0, 1]).
std::vector<double> coordinates_of(const CalibrationProblem& problem, const ParameterSet& set);

/// The model's curve of one test interpolated at the measured points: one vector per quantity.
/// Empty optional when the model fails on this test (or the set is impossible).
std::optional<std::vector<std::vector<double>>> simulate(const LabTest& test,
                                                         const ModelPtr& model);

/// Runs one test and returns its whole curve (for figures and synthetic data).
ElementResult run_lab_test(const LabTest& test, const ModelPtr& model);

/// Residuals of one test for given simulated values: per quantity and point,
/// sqrt(w_test w_q / N) (simulated - measured) / scale. Their sum of squares is the weighted
/// mean squared normalised error.
std::vector<double> test_residuals(const LabTest& test,
                                   const std::vector<std::vector<double>>& simulated);
/// Number of residuals of a test.
std::size_t residual_count(const LabTest& test);

/// The RMS of (simulated - measured)/scale of one quantity (unweighted): the quality figure of
/// the report, comparable with the noise of the data divided by the same scale.
double normalised_rms(const MeasuredQuantity& quantity, const std::vector<double>& simulated);

/// Replaces the measured values of every test by the model's curve of `truth` at the measured
/// points, with Gaussian noise of standard deviation `noise_fraction` times each quantity's
/// range in that test (seeded, reproducible). Used to make synthetic data and the checks.
void make_synthetic_data(CalibrationProblem& problem, const ParameterSet& truth,
                         double noise_fraction, unsigned seed);

}  // namespace pilempm::calibration
