// Bauer's (1996) compression law (docs/model.md §2-§6, §4) against its closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "pilempm/analytic/bauer.hpp"
#include "pilempm/core/error.hpp"

namespace pilempm {
namespace {

// e_p = e_p0 exp[-(3 p / h_s)^n], written out here for the original set (h_s = 4 GPa, n = 0.42).
TEST(Bauer, TableMatchesClosedForm) {
  const HypoplasticParameters original = hypoplastic_set("original");
  const std::vector<double> pressures = {0.0, 10.0e3, 100.0e3, 1.0e6, 10.0e6, 30.0e6};
  const std::vector<BauerRow> rows = bauer_table(original, pressures);
  ASSERT_EQ(rows.size(), pressures.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    SCOPED_TRACE("p = " + std::to_string(pressures[i]) + " Pa");
    const double factor = std::exp(-std::pow(3.0 * pressures[i] / 4.0e9, 0.42));
    EXPECT_DOUBLE_EQ(rows[i].mean_stress, pressures[i]);
    EXPECT_NEAR(rows[i].limits.e_d, 0.548 * factor, 1e-14);
    EXPECT_NEAR(rows[i].limits.e_c, 0.929 * factor, 1e-14);
    EXPECT_NEAR(rows[i].limits.e_i, 1.08 * factor, 1e-14);
    EXPECT_NEAR(bauer_void_ratio(0.68, 4.0e9, 0.42, pressures[i]), 0.68 * factor, 1e-14);
  }
}

// At 3p = h_s the exponent is 1 whatever n is: every void ratio is its zero-pressure value / e.
TEST(Bauer, AtThreePEqualToHardnessTheFactorIsOneOverE) {
  for (const double n : {0.2, 0.42, 0.8}) {
    EXPECT_NEAR(bauer_void_ratio(0.9, 2.0e9, n, 2.0e9 / 3.0), 0.9 / std::exp(1.0), 1e-14);
  }
}

// A softer sand (smaller h_s) compresses more at the same pressure.
TEST(Bauer, SofterSandCompressesMore) {
  const double p = 1.0e6;
  EXPECT_LT(bauer_void_ratio(0.929, 2.0e9, 0.42, p), bauer_void_ratio(0.929, 4.0e9, 0.42, p));
}

void expect_invalid_table(const HypoplasticParameters& parameters, double p,
                          const std::string& key) {
  const std::vector<double> pressures = {p};
  try {
    bauer_table(parameters, pressures);
    ADD_FAILURE() << "no InvalidValue for key " << key;
  } catch (const InvalidValue& error) {
    EXPECT_EQ(error.key(), key);
    EXPECT_NE(std::string(error.what()).find(key), std::string::npos) << error.what();
  }
}

TEST(Bauer, InvalidInputNamesTheKey) {
  const HypoplasticParameters original = hypoplastic_set("original");
  expect_invalid_table(original, -1.0, "p_Pa");
  HypoplasticParameters bad = original;
  bad.h_s = 0.0;
  expect_invalid_table(bad, 1.0e5, "h_s_Pa");
  bad = original;
  bad.n = 1.2;
  expect_invalid_table(bad, 1.0e5, "n");
  bad = original;
  bad.e_c0 = 0.5;  // below e_d0
  expect_invalid_table(bad, 1.0e5, "e_c0");
  bad = original;
  bad.e_i0 = 0.9;  // below e_c0
  expect_invalid_table(bad, 1.0e5, "e_i0");
  EXPECT_THROW(bauer_void_ratio(-0.5, 4.0e9, 0.42, 1.0e5), InvalidValue);
}

}  // namespace
}  // namespace pilempm
