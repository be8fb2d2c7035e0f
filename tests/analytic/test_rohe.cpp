// Rohe (2010) stress-dependent reference void ratios (docs/study.md §3).
#include <gtest/gtest.h>

#include <string>

#include "pilempm/constitutive/hypoplastic/rohe_void_ratios.hpp"
#include "pilempm/core/error.hpp"

namespace pilempm {
namespace {

// The brief: at 10 MPa the formula gives 0.887 / 0.524 / 1.020 (three decimals).
TEST(Rohe, BriefValuesAt10MPa) {
  const RoheReferenceVoidRatios result = rohe_reference_void_ratios(10.0e6);
  EXPECT_NEAR(result.e_c0, 0.887, 5e-4);
  EXPECT_NEAR(result.e_d0, 0.524, 5e-4);
  EXPECT_NEAR(result.e_i0, 1.020, 5e-4);
}

// At zero stress the argument is 2.1669, so each value is its constant minus slope * ln 2.1669.
TEST(Rohe, ZeroStressIsTheConstantTerm) {
  const double log_argument = 0.773298;  // ln 2.1669, to six decimals
  const RoheReferenceVoidRatios result = rohe_reference_void_ratios(0.0);
  EXPECT_NEAR(result.e_c0, 0.9501 - 0.0702 * log_argument, 1e-6);
  EXPECT_NEAR(result.e_d0, 0.6768 - 0.1698 * log_argument, 1e-6);
  EXPECT_NEAR(result.e_i0, 1.0926 - 0.0807 * log_argument, 1e-6);
}

// Over the study's range (to 30 MPa) the three stay ordered e_d0 < e_c0 < e_i0 and fall with
// stress.
TEST(Rohe, OrderedAndFallingWithStress) {
  RoheReferenceVoidRatios previous = rohe_reference_void_ratios(0.0);
  for (double sigma_MPa = 0.5; sigma_MPa <= 30.0; sigma_MPa += 0.5) {
    const RoheReferenceVoidRatios result = rohe_reference_void_ratios(sigma_MPa * 1.0e6);
    EXPECT_LT(result.e_d0, result.e_c0);
    EXPECT_LT(result.e_c0, result.e_i0);
    EXPECT_LT(result.e_c0, previous.e_c0);
    EXPECT_LT(result.e_d0, previous.e_d0);
    EXPECT_LT(result.e_i0, previous.e_i0);
    previous = result;
  }
}

TEST(Rohe, NegativeStressNamesTheKey) {
  try {
    rohe_reference_void_ratios(-1.0);
    ADD_FAILURE() << "no InvalidValue";
  } catch (const InvalidValue& error) {
    EXPECT_EQ(error.key(), "sigma_v_Pa");
    EXPECT_NE(std::string(error.what()).find("sigma_v_Pa"), std::string::npos);
  }
}

}  // namespace
}  // namespace pilempm
