// Branches and secant moduli of oedometer curves, on curves whose answers are known exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "pilempm/core/error.hpp"
#include "pilempm/study/oedometer_stiffness.hpp"

namespace pilempm {
namespace {

TEST(LoadingBranches, SplitsACyclicHistoryAtEachReversal) {
  const std::vector<double> stress = {10, 20, 30, 30, 20, 10, 20, 30};
  const std::vector<LoadingBranch> b = loading_branches(stress);
  ASSERT_EQ(b.size(), 3u);
  EXPECT_TRUE(b[0].loading);
  EXPECT_EQ(b[0].first, 0u);
  EXPECT_EQ(b[0].last, 3u);  // the repeated 30 stays in the loading branch
  EXPECT_FALSE(b[1].loading);
  EXPECT_EQ(b[1].first, 3u);
  EXPECT_EQ(b[1].last, 5u);
  EXPECT_TRUE(b[2].loading);
  EXPECT_EQ(b[2].first, 5u);
  EXPECT_EQ(b[2].last, 7u);
}

TEST(LoadingBranches, RejectsTooShortOrNonFiniteCurves) {
  EXPECT_THROW(loading_branches(std::vector<double>{10}), InvalidValue);
  EXPECT_THROW(loading_branches(std::vector<double>{10, std::nan("")}), InvalidValue);
}

TEST(SecantModulus, IsExactOnALinearCurveBetweenRows) {
  // sigma = 10 kPa + M eps with M = 20 MPa, sampled at uneven strains.
  const double M = 20e6;
  const std::vector<double> strain = {0.0, 1e-4, 3e-4, 7e-4, 1e-3};
  std::vector<double> stress;
  for (double e : strain) stress.push_back(10e3 + M * e);
  const LoadingBranch branch = loading_branches(stress).front();
  // 12 kPa and 23 kPa lie between rows: interpolation is exact on a straight line.
  EXPECT_NEAR(secant_modulus(stress, strain, branch, 12e3, 23e3), M, 1e-6 * M);
  EXPECT_THROW(secant_modulus(stress, strain, branch, 5e3, 20e3), InvalidValue);   // below
  EXPECT_THROW(secant_modulus(stress, strain, branch, 12e3, 40e3), InvalidValue);  // above
}

TEST(CyclicOedometer, ModuliAndAccumulatedStrainOfAPiecewiseLinearCurve) {
  // First loading 10 -> 40 kPa at 10 MPa (with a stiffer first increment), unloading to 20 kPa
  // at 100 MPa, reloading to 40 kPa at 50 MPa: the cycle leaves 0.4e-3 - 0.2e-3 = 0.2e-3 of
  // vertical strain behind.
  std::vector<double> stress, strain;
  const auto add = [&](double s, double e) {
    stress.push_back(s);
    strain.push_back(e);
  };
  add(10e3, 0.0);
  add(15e3, 0.25e-3);  // 20 MPa over the first increment
  add(20e3, 0.75e-3);  // 10 MPa from here on
  add(40e3, 2.75e-3);
  add(30e3, 2.65e-3);  // unloading at 100 MPa
  add(20e3, 2.55e-3);
  add(30e3, 2.75e-3);  // reloading at 50 MPa
  add(40e3, 2.95e-3);
  const CyclicOedometerStiffness r = analyse_cyclic_oedometer(stress, strain);
  EXPECT_DOUBLE_EQ(r.initial_stress, 10e3);
  EXPECT_DOUBLE_EQ(r.first_increment_stress, 15e3);
  EXPECT_NEAR(r.first_increment_modulus, 20e6, 1e-3);
  EXPECT_NEAR(r.initial_secant_modulus, 10e3 / 0.75e-3, 1e-3);  // 10 -> 20 kPa
  EXPECT_DOUBLE_EQ(r.reload_from, 20e3);
  EXPECT_DOUBLE_EQ(r.reload_to, 40e3);
  EXPECT_NEAR(r.reload_secant_modulus, 50e6, 1e-3);
  EXPECT_DOUBLE_EQ(r.strain_after_first_loading, 2.75e-3);
  EXPECT_DOUBLE_EQ(r.final_strain, 2.95e-3);
  EXPECT_NEAR(r.accumulated_strain, 0.2e-3, 1e-15);
  EXPECT_EQ(r.unload_reload_cycles, 1);
}

TEST(CyclicOedometer, NeedsAFirstLoadingToTwiceTheStart) {
  EXPECT_THROW(analyse_cyclic_oedometer(std::vector<double>{10e3, 15e3, 12e3},
                                        std::vector<double>{0.0, 1e-4, 0.9e-4}),
               InvalidValue);
  EXPECT_THROW(analyse_cyclic_oedometer(std::vector<double>{10e3, 30e3}, std::vector<double>{0.0}),
               InvalidValue);
}

TEST(CyclicOedometer, NoAccumulatedStrainWhenTheCurveEndsElsewhere) {
  const CyclicOedometerStiffness r = analyse_cyclic_oedometer(
      std::vector<double>{10e3, 40e3, 20e3}, std::vector<double>{0.0, 3e-3, 2.8e-3});
  EXPECT_TRUE(std::isnan(r.accumulated_strain));
  EXPECT_EQ(r.reload_secant_modulus, 0.0);  // no reloading branch
}

}  // namespace
}  // namespace pilempm
