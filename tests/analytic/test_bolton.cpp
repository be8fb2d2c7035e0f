// Bolton (1986) with Schanz & Vermeer's dilatancy angle against the study's table (docs/study.md
// §3).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "pilempm/analytic/bolton.hpp"
#include "pilempm/core/error.hpp"

namespace pilempm {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRelativeDensity = 0.95;
constexpr double kPhiCDeg = 31.0;

// The brief's values, to the three decimals it gives.
TEST(Bolton, BriefTableAt500kPa) {
  const BoltonResult result = bolton(kRelativeDensity, kPhiCDeg, 500.0e3);
  EXPECT_NEAR(result.relative_dilatancy_index, 2.596, 5e-4);
  EXPECT_NEAR(result.phi_max_deg, 38.788, 5e-4);
  EXPECT_NEAR(result.psi_max_deg, 16.277, 5e-4);
}

// At 30 MPa I_R is negative and kept so (not clipped to 0): the sand contracts.
TEST(Bolton, BriefTableAt30MPaKeepsNegativeIndex) {
  const BoltonResult result = bolton(kRelativeDensity, kPhiCDeg, 30.0e6);
  EXPECT_NEAR(result.relative_dilatancy_index, -1.294, 5e-4);
  EXPECT_NEAR(result.phi_max_deg, 27.119, 5e-4);
  EXPECT_NEAR(result.psi_max_deg, -13.930, 5e-4);
  EXPECT_LT(result.dilatancy_rate, 0.0);
}

// The other pressures of the table against the formulas written out here, independently of the
// library: I_R = I_D (10 - ln p') - 1 (p' in kPa), phi = phi_c + 3 I_R, rate = 0.3 I_R,
// sin psi = rate / (2 + rate).
TEST(Bolton, WholeTableMatchesFormula) {
  for (const double p_kPa : {500.0, 2000.0, 4000.0, 6000.0, 16000.0, 30000.0}) {
    SCOPED_TRACE("p = " + std::to_string(p_kPa) + " kPa");
    const double index = kRelativeDensity * (10.0 - std::log(p_kPa)) - 1.0;
    const double rate = 0.3 * index;
    const double sin_psi = rate / (2.0 + rate);
    const BoltonResult result = bolton(kRelativeDensity, kPhiCDeg, p_kPa * 1.0e3);
    EXPECT_NEAR(result.relative_dilatancy_index, index, 1e-12);
    EXPECT_NEAR(result.phi_max_deg, kPhiCDeg + 3.0 * index, 1e-12);
    EXPECT_NEAR(result.dilatancy_rate, rate, 1e-12);
    EXPECT_NEAR(result.sin_psi_max, sin_psi, 1e-12);
    EXPECT_NEAR(result.psi_max_deg, std::asin(sin_psi) * 180.0 / kPi, 1e-10);
  }
}

// Schanz & Vermeer: the dilatancy angle has the sign of the dilatancy rate, and I_R falls with p.
TEST(Bolton, DilatancyFallsWithPressure) {
  double previous = bolton(kRelativeDensity, kPhiCDeg, 100.0e3).relative_dilatancy_index;
  for (const double p_kPa : {500.0, 2000.0, 4000.0, 6000.0, 16000.0, 30000.0}) {
    const BoltonResult result = bolton(kRelativeDensity, kPhiCDeg, p_kPa * 1.0e3);
    EXPECT_LT(result.relative_dilatancy_index, previous);
    EXPECT_EQ(std::signbit(result.psi_max_deg), std::signbit(result.dilatancy_rate));
    previous = result.relative_dilatancy_index;
  }
}

// With I_D = 0 the index is -1 at every pressure: phi_max = phi_c - 3.
TEST(Bolton, LoosestStateGivesMinusOne) {
  EXPECT_DOUBLE_EQ(bolton(0.0, kPhiCDeg, 100.0e3).relative_dilatancy_index, -1.0);
  EXPECT_DOUBLE_EQ(bolton(0.0, kPhiCDeg, 100.0e3).phi_max_deg, kPhiCDeg - 3.0);
}

void expect_invalid(double relative_density, double phi_c_deg, double mean_stress,
                    const std::string& key) {
  try {
    bolton(relative_density, phi_c_deg, mean_stress);
    ADD_FAILURE() << "no InvalidValue for key " << key;
  } catch (const InvalidValue& error) {
    EXPECT_EQ(error.key(), key);
    EXPECT_NE(std::string(error.what()).find(key), std::string::npos) << error.what();
  }
}

TEST(Bolton, InvalidInputNamesTheKey) {
  expect_invalid(1.5, kPhiCDeg, 100.0e3, "I_D");
  expect_invalid(-0.1, kPhiCDeg, 100.0e3, "I_D");
  expect_invalid(std::nan(""), kPhiCDeg, 100.0e3, "I_D");
  expect_invalid(0.5, 0.0, 100.0e3, "phi_c_deg");
  expect_invalid(0.5, 90.0, 100.0e3, "phi_c_deg");
  expect_invalid(0.5, kPhiCDeg, 0.0, "p_Pa");
  expect_invalid(0.5, kPhiCDeg, -1.0e3, "p_Pa");
  // 1e-6 kPa: I_R = 10 + 0.95 * 13.8 - 1 = 21.6, phi_max = 96 deg > 90: outside Bolton's range.
  expect_invalid(0.95, kPhiCDeg, 1.0e-3, "p_Pa");
}

}  // namespace
}  // namespace pilempm
