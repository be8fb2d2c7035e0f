// Calibration: the misfit, the recovery of known parameter sets from noisy synthetic data made
// by pilempm itself and the stability of the fit from different starting sets
// (docs/calibration.md). The use of the fitted set in a case file is tested with the writer of
// parameters.toml (tests/io/test_calibration_output.cpp).
#include <gtest/gtest.h>

#include <cmath>

#include "../support/calibration_builders.hpp"
#include "pilempm/calibration/fit.hpp"

namespace {

using namespace pilempm;
using namespace pilempm::calibration;

using test_support::kKPa;
using test_support::lab;
using test_support::problem_of;
using test_support::truth_of;

constexpr double kNoise = 0.01;  // standard deviation: 1 % of each quantity's range

// The tolerances of docs/calibration.md for the parameters these tests determine.
void expect_recovered(const ParameterSet& fitted, const ParameterSet& truth) {
  const HypoplasticParameters &f = fitted.hypoplastic, &t = truth.hypoplastic;
  EXPECT_NEAR(f.phi_c_deg, t.phi_c_deg, 0.5);
  EXPECT_NEAR(f.h_s / t.h_s, 1.0, 0.15);
  EXPECT_NEAR(f.n, t.n, 0.03);
  EXPECT_NEAR(f.e_d0, t.e_d0, 0.025);
  EXPECT_NEAR(f.e_c0, t.e_c0, 0.02);
  EXPECT_NEAR(f.alpha, t.alpha, 0.025);
  EXPECT_NEAR(f.beta, t.beta, 0.2);
}

// The fitted curves match the data to the noise: over all quantities the mean squared
// normalised error is within 30 % of the noise's variance, and no quantity is off by more than
// twice the noise.
void expect_fit_to_noise(const FitResult& r) {
  ASSERT_FALSE(r.quantities.empty());
  double mean_square = 0.0;
  for (const QuantityFit& q : r.quantities) {
    EXPECT_LT(q.rms, 2.0 * kNoise) << "test " << q.test << " quantity " << q.quantity;
    mean_square += q.rms * q.rms / static_cast<double>(r.quantities.size());
  }
  EXPECT_LT(mean_square, 1.3 * kNoise * kNoise);
}

TEST(CalibrationMisfit, ExactDataOfTheTruthHaveZeroMisfitAndOtherSetsDoNot) {
  CalibrationProblem p = problem_of("original", 0.60, 0.80, 60);
  // A cyclic oedometer too: its points are matched along the loading history.
  OedometerTest cyclic;
  cyclic.sigma_v0 = 10 * kKPa;
  cyclic.K0 = 0.485;
  cyclic.sigma_v_targets = {400 * kKPa, 100 * kKPa, 400 * kKPa};
  cyclic.steps_per_segment = 40;
  p.tests.push_back(lab("oed-cyclic", cyclic, 0.7));
  const ParameterSet truth = truth_of("original");
  make_synthetic_data(p, truth, 0.0, 1);
  Evaluator evaluator(p);
  const auto at_truth = evaluator.residuals(truth);
  ASSERT_TRUE(at_truth);
  double sum = 0.0;
  for (double r : *at_truth) sum += r * r;
  EXPECT_LT(sum, 1e-20);
  const auto other = evaluator.residuals(truth_of("loose-fit"));
  ASSERT_TRUE(other);
  sum = 0.0;
  for (double r : *other) sum += r * r;
  EXPECT_GT(sum, 1e-4);
  EXPECT_EQ(evaluator.runs(), 2 * static_cast<long>(p.tests.size()));
}

TEST(CalibrationMisfit, ImpossibleSetsAreRejectedNotRun) {
  CalibrationProblem p = problem_of("original", 0.60, 0.80, 30);
  make_synthetic_data(p, truth_of("original"), 0.0, 1);
  Evaluator evaluator(p);
  ParameterSet bad = truth_of("original");
  bad.hypoplastic.e_d0 = 1.0;  // above e_c0
  EXPECT_FALSE(evaluator.residuals(bad));
  EXPECT_EQ(evaluator.runs(), 0);
}

TEST(CalibrationRecovery, OriginalSetFromNoisyData) {
  CalibrationProblem p = problem_of("modified-loose", 0.60, 0.80, 80);
  const ParameterSet truth = truth_of("original");
  make_synthetic_data(p, truth, kNoise, 1);
  const FitResult r = calibrate(p);
  expect_recovered(r.fitted, truth);
  expect_fit_to_noise(r);
  EXPECT_LT(r.final_misfit, 0.01 * r.start_misfit);
  // e_i0 is seen by none of these tests well: the sensitivity says so, and it has the largest
  // relative standard error of all.
  const auto worst = std::max_element(
      r.sensitivity.begin(), r.sensitivity.end(), [](const Sensitivity& a, const Sensitivity& b) {
        return a.standard_error_fraction < b.standard_error_fraction;
      });
  ASSERT_NE(worst, r.sensitivity.end());
  EXPECT_EQ(worst->id, ParameterId::e_i0);
  EXPECT_FALSE(worst->determined);
}

TEST(LongCalibrationRecovery, ModifiedMediumDenseSetFromNoisyData) {
  CalibrationProblem p = problem_of("original", 0.58, 0.78, 150);
  const ParameterSet truth = truth_of("modified-medium-dense");
  make_synthetic_data(p, truth, kNoise, 2);
  const FitResult r = calibrate(p);
  expect_recovered(r.fitted, truth);
  expect_fit_to_noise(r);
}

TEST(LongCalibrationRecovery, LooseSetFromNoisyData) {
  CalibrationProblem p = problem_of("original", 0.62, 0.82, 150);
  const ParameterSet truth = truth_of("loose-fit");
  make_synthetic_data(p, truth, kNoise, 3);
  const FitResult r = calibrate(p);
  expect_recovered(r.fitted, truth);
  expect_fit_to_noise(r);
}

// Both stages from three different starting sets end at the same parameters, within a fraction
// of the tolerances of the recovery. (The refinement alone from the third, far start ends in
// another local minimum, docs/calibration.md: the physics-ordered start is what makes the fit
// independent of where it starts.)
TEST(CalibrationStability, ThreeStartingSetsEndAtTheSameParameters) {
  CalibrationProblem p = problem_of("original", 0.60, 0.80, 60);
  make_synthetic_data(p, truth_of("original"), kNoise, 4);
  std::vector<ParameterSet> starts = {truth_of("modified-loose"), truth_of("loose-fit"),
                                      truth_of("original")};
  // A third start far from both: stiff, steep, with high alpha and beta.
  HypoplasticParameters& far = starts[2].hypoplastic;
  far = {34.0, 8000e6, 0.3, 0.6, 1.0, 1.2, 0.25, 1.5, {}};
  std::vector<ParameterSet> fitted;
  for (const ParameterSet& start : starts) {
    p.base = start;
    fitted.push_back(calibrate(p).fitted);
  }
  for (std::size_t k = 1; k < fitted.size(); ++k) {
    const HypoplasticParameters &a = fitted[0].hypoplastic, &b = fitted[k].hypoplastic;
    EXPECT_NEAR(a.phi_c_deg, b.phi_c_deg, 0.2) << "start " << k;
    EXPECT_NEAR(a.h_s / b.h_s, 1.0, 0.05) << "start " << k;
    EXPECT_NEAR(a.n, b.n, 0.01) << "start " << k;
    EXPECT_NEAR(a.e_d0, b.e_d0, 0.01) << "start " << k;
    EXPECT_NEAR(a.e_c0, b.e_c0, 0.01) << "start " << k;
    EXPECT_NEAR(a.alpha, b.alpha, 0.01) << "start " << k;
    EXPECT_NEAR(a.beta, b.beta, 0.05) << "start " << k;
  }
}

TEST(CalibrationParameters, NormalisedCoordinatesRoundTripOnLinearAndLogScales) {
  const FreeParameter linear{ParameterId::phi_c_deg, 25, 40, {}};
  const FreeParameter logarithmic{ParameterId::h_s_MPa, 500, 20000, {}};
  EXPECT_NEAR(linear.value(linear.coordinate(31.0)), 31.0, 1e-12);
  EXPECT_NEAR(logarithmic.value(logarithmic.coordinate(4000.0)), 4000.0, 1e-9);
  EXPECT_NEAR(logarithmic.value(0.5), std::sqrt(500.0 * 20000.0), 1e-9);
  for (ParameterId id : all_parameters()) {
    ParameterSet s = truth_of("original");
    set(s, id, 0.777);
    EXPECT_DOUBLE_EQ(get(s, id), 0.777) << parameter_name(id);
    EXPECT_EQ(parameter_from_name(parameter_name(id)), id);
  }
}

}  // namespace
