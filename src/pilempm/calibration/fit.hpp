#pragma once
// The two stages of a calibration (docs/calibration.md): a physics-ordered start from the
// measured curves, then a bounded least-squares refinement over all tests at once with the
// element tests run by pilempm's own driver, and the sensitivity of the fit at its end.
#include <Eigen/Dense>
#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "pilempm/calibration/calibration_problem.hpp"

namespace pilempm::calibration {

/// Runs the tests of a problem for parameter sets given by normalised coordinates, in parallel
/// over tests and finite-difference columns, and counts the element-test runs.
class Evaluator {
 public:
  explicit Evaluator(const CalibrationProblem& problem);

  /// All residuals at `u`; nullopt when the set is impossible or the model fails on a test.
  std::optional<std::vector<double>> residuals(const std::vector<double>& u);
  /// The residuals of a complete set, for the given tests only (all when `tests` is empty).
  std::optional<std::vector<double>> residuals(const ParameterSet& set,
                                               const std::vector<std::size_t>& tests = {});
  /// Forward-difference Jacobian at `u` (residuals `r0` there); false when no column could be
  /// formed for some parameter.
  bool jacobian(const std::vector<double>& u, const std::vector<double>& r0, Eigen::MatrixXd& J);

  std::size_t residual_count() const { return residual_count_; }
  long runs() const { return runs_.load(); }
  const CalibrationProblem& problem() const { return problem_; }

  /// Step of the finite differences in normalised coordinates (0.1 % of each bound range).
  static constexpr double kStep = 1e-3;

 private:
  // Residuals of each of the given tests at each of the given sets (sets x tests tasks run in
  // parallel); an empty inner optional for a failed set.
  std::vector<std::optional<std::vector<double>>> run_sets(const std::vector<ParameterSet>& sets,
                                                           const std::vector<std::size_t>& tests);

  const CalibrationProblem& problem_;
  std::size_t residual_count_ = 0;
  std::atomic<long> runs_{0};
};

/// Progress of a fit, reported after each step.
struct FitProgress {
  std::string stage;        ///< "start", "refine", "sensitivity"
  int step = 0;             ///< iteration of the stage
  int max_steps = 0;        ///< its limit
  long runs = 0;            ///< element tests run so far
  double seconds = 0;       ///< since the fit began
  double misfit = 0;        ///< sum of squared residuals
  double seconds_left = 0;  ///< an estimate (at most: the iteration limit)
  std::string message;
};
using FitObserver = std::function<void(const FitProgress&)>;

/// How the physics-ordered start set one parameter.
struct StartNote {
  ParameterId id = ParameterId::phi_c_deg;
  double value = 0.0;  ///< case-file units
  std::string how;
};

/// One row of the refinement history.
struct HistoryRow {
  std::string stage;
  int step = 0;
  long runs = 0;
  double seconds = 0.0;
  double misfit = 0.0;
  ParameterSet parameters;
};

/// The fit of one quantity of one test.
struct QuantityFit {
  std::size_t test = 0;  ///< index into problem.tests
  std::size_t quantity = 0;
  double rms = 0.0;  ///< normalised RMS error (by the quantity's range), see normalised_rms
  std::vector<double> simulated;
};

/// How well the data determine one free parameter.
struct Sensitivity {
  ParameterId id = ParameterId::phi_c_deg;
  /// Relative rise of the misfit when the parameter moves by 10 % of its bound range (linear
  /// model at the optimum).
  double misfit_rise_10pct = 0.0;
  double standard_error = 0.0;           ///< case-file units, from the Gauss-Newton covariance
  double standard_error_fraction = 0.0;  ///< standard error / bound range
  bool determined = true;
  std::string note;
};

struct FitResult {
  ParameterSet start;  ///< after the physics-ordered start
  std::vector<StartNote> start_notes;
  ParameterSet fitted;
  double start_misfit = 0.0;
  double final_misfit = 0.0;
  std::vector<QuantityFit> quantities;
  std::vector<Sensitivity> sensitivity;
  std::vector<std::string> correlations;  ///< "a ~ b: 0.97" for |correlation| > 0.9
  std::vector<HistoryRow> history;
  std::string method;
  std::string termination;
  int iterations = 0;
  long runs = 0;
  long runs_start = 0, runs_refine = 0, runs_sensitivity = 0;
  double seconds = 0.0;
  double seconds_start = 0.0, seconds_refine = 0.0, seconds_sensitivity = 0.0;
  std::vector<std::string> warnings;
};

/// Stage 1: the physics-ordered start (docs/calibration.md lists its rules). Parameters with a
/// user-given start value keep it.
ParameterSet physics_start(const CalibrationProblem& problem, Evaluator& evaluator,
                           std::vector<StartNote>& notes);

/// Both stages and the sensitivity. Throws Error when the starting set already fails.
FitResult calibrate(const CalibrationProblem& problem, const FitObserver& observer = {});

}  // namespace pilempm::calibration
