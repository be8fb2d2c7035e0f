// Validation of the hypoplastic parameters, the named sets of docs/model.md §2-§6, the integrator
// settings, and the two initial void ratio conventions.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/constitutive/hypoplastic/hypoplastic_parameters.hpp"
#include "pilempm/core/error.hpp"

namespace pilempm {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Runs `check` and expects an InvalidValue whose message names `key`; returns the message.
std::string expect_rejected(const std::function<void()>& check, const std::string& key,
                            const std::string& what_was_changed) {
  try {
    check();
  } catch (const InvalidValue& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(key), std::string::npos)
        << what_was_changed << ": message does not name " << key << ": " << message;
    EXPECT_NE(error.key().find(key), std::string::npos) << what_was_changed;
    return message;
  } catch (const std::exception& other) {
    ADD_FAILURE() << what_was_changed
                  << ": threw something else than InvalidValue: " << other.what();
    return {};
  }
  ADD_FAILURE() << what_was_changed << ": was accepted";
  return {};
}

void expect_hypoplastic_rejects(const std::string& key, double HypoplasticParameters::*member,
                                double bad_value) {
  HypoplasticParameters parameters = hypoplastic_set("original");
  parameters.*member = bad_value;
  const std::string label = key + " = " + std::to_string(bad_value);
  expect_rejected([&] { parameters.validate(); }, key, label);
  // The model constructor validates too, so a bad set never reaches the integrator.
  expect_rejected([&] { Hypoplastic model(parameters); }, key, label + " (constructor)");
}

void expect_igs_rejects(const std::string& key, double IntergranularStrainParameters::*member,
                        double bad_value) {
  IntergranularStrainParameters igs = intergranular_strain_set("IGS3");
  igs.*member = bad_value;
  const std::string label = key + " = " + std::to_string(bad_value);
  expect_rejected([&] { igs.validate(); }, key, label);
  expect_rejected([&] { Hypoplastic model(hypoplastic_set("original"), igs); }, key,
                  label + " (constructor)");
}

void expect_integrator_rejects(const std::string& key, const IntegratorSettings& settings) {
  expect_rejected([&] { settings.validate(); }, key, key);
  expect_rejected(
      [&] {
        Hypoplastic model(hypoplastic_set("original"), intergranular_strain_set("IGS3"), settings);
      },
      key, key + " (constructor)");
}

using P = HypoplasticParameters;
using I = IntergranularStrainParameters;

TEST(HypoplasticParameters, EveryCheckRejectsItsBadValueNamingTheKey) {
  for (double bad : {0.0, -5.0, 90.0, 120.0, kNaN})
    expect_hypoplastic_rejects("phi_c_deg", &P::phi_c_deg, bad);
  for (double bad : {0.0, -1.0e9, kNaN, kInf}) expect_hypoplastic_rejects("h_s", &P::h_s, bad);
  for (double bad : {0.0, -0.1, 1.0, 1.5, kNaN}) expect_hypoplastic_rejects("n", &P::n, bad);
  for (double bad : {0.0, -0.5, kNaN}) expect_hypoplastic_rejects("e_d0", &P::e_d0, bad);
  // e_c0 <= e_d0 (0.548), and e_i0 <= e_c0 (0.929).
  for (double bad : {0.548, 0.5, kNaN}) expect_hypoplastic_rejects("e_c0", &P::e_c0, bad);
  for (double bad : {0.929, 0.9, kNaN, kInf}) expect_hypoplastic_rejects("e_i0", &P::e_i0, bad);
  for (double bad : {-0.01, -1.0, kNaN}) expect_hypoplastic_rejects("alpha", &P::alpha, bad);
  for (double bad : {-0.01, -1.0, kNaN}) expect_hypoplastic_rejects("beta", &P::beta, bad);
  // alpha so large that f_b's denominator 3 + a^2 - a sqrt3 ((e_i0-e_d0)/(e_c0-e_d0))^alpha < 0.
  expect_hypoplastic_rejects("alpha", &P::alpha, 10.0);

  for (double bad : {-1.0e-4, kNaN}) expect_igs_rejects("R", &I::R, bad);
  for (double bad : {0.99, 0.0, kNaN}) expect_igs_rejects("m_T", &I::m_T, bad);
  for (double bad : {1.99, 1.0, kNaN}) expect_igs_rejects("m_R", &I::m_R, bad);  // m_T = 2
  for (double bad : {0.0, -1.0, kNaN}) expect_igs_rejects("beta_r", &I::beta_r, bad);
  for (double bad : {0.0, -1.0, kNaN}) expect_igs_rejects("chi", &I::chi, bad);

  for (double bad : {0.0, -1.0e-3, 0.11, kNaN}) {
    IntegratorSettings settings;
    settings.tolerance = bad;
    expect_integrator_rejects("tolerance", settings);
  }
  for (double bad : {0.0, -1.0, kNaN, kInf}) {
    IntegratorSettings settings;
    settings.min_mean_stress = bad;
    expect_integrator_rejects("min_mean_stress", settings);
  }
  {
    IntegratorSettings settings;
    settings.fixed_substeps = -1;
    expect_integrator_rejects("fixed_substeps", settings);
  }
  {
    IntegratorSettings settings;
    settings.max_substeps = 0;
    expect_integrator_rejects("max_substeps", settings);
  }
  for (double bad : {0.0, 1.0, -1.0e-6}) {
    IntegratorSettings settings;
    settings.min_substep = bad;
    expect_integrator_rejects("min_substep", settings);
  }
}

TEST(HypoplasticParameters, BoundaryValuesThatAreAllowedAreAccepted) {
  HypoplasticParameters parameters = hypoplastic_set("original");
  parameters.alpha = 0.0;
  parameters.beta = 0.0;
  EXPECT_NO_THROW(parameters.validate());
  // With R = 0 the intergranular strain is off and its other parameters are not looked at.
  IntergranularStrainParameters off{0.5, 0.5, 0.0, -1.0, -1.0};
  EXPECT_FALSE(off.enabled());
  EXPECT_NO_THROW(off.validate());
  // m_R = m_T = 1 is the basic model with the intergranular strain bookkeeping: allowed.
  IntergranularStrainParameters unit{1.0, 1.0, 1.0e-4, 1.0, 1.0};
  EXPECT_TRUE(unit.enabled());
  EXPECT_NO_THROW(unit.validate());
  IntegratorSettings settings;
  settings.tolerance = 0.1;
  EXPECT_NO_THROW(settings.validate());
}

TEST(HypoplasticParameters, EveryNamedSetValidates) {
  const auto names = hypoplastic_set_names();
  EXPECT_GE(names.size(), 4u);
  for (const auto& name : names) {
    SCOPED_TRACE(name);
    EXPECT_NO_THROW(hypoplastic_set(name).validate());
  }
  const auto igs_names = intergranular_strain_set_names();
  EXPECT_GE(igs_names.size(), 5u);
  for (const auto& name : igs_names) {
    SCOPED_TRACE(name);
    const auto igs = intergranular_strain_set(name);
    EXPECT_NO_THROW(igs.validate());
    EXPECT_EQ(igs.enabled(), name != "none");
  }
}

TEST(HypoplasticParameters, NamedSetsEqualTheBriefTable) {
  struct Row {
    const char* name;
    double phi_c, h_s_MPa, n, e_d0, e_c0, e_i0, alpha, beta;
  };
  // docs/model.md §2-§6, Baskarp sand (the modified sets keep n = 0.42).
  const Row rows[] = {
      {"original", 31, 4000, 0.42, 0.548, 0.929, 1.08, 0.12, 0.96},
      {"loose-fit", 31, 2000, 0.42, 0.548, 0.929, 1.08, 0.12, 0.96},
      {"modified-medium-dense", 30, 4000, 0.42, 0.51, 0.88, 1.01, 0.03, 0.96},
      {"modified-loose", 30, 2000, 0.42, 0.51, 0.88, 1.01, 0.03, 0.96},
  };
  for (const auto& row : rows) {
    SCOPED_TRACE(row.name);
    const auto p = hypoplastic_set(row.name);
    EXPECT_EQ(p.phi_c_deg, row.phi_c);
    EXPECT_EQ(p.h_s, row.h_s_MPa * 1.0e6);
    EXPECT_EQ(p.n, row.n);
    EXPECT_EQ(p.e_d0, row.e_d0);
    EXPECT_EQ(p.e_c0, row.e_c0);
    EXPECT_EQ(p.e_i0, row.e_i0);
    EXPECT_EQ(p.alpha, row.alpha);
    EXPECT_EQ(p.beta, row.beta);
  }
  struct IgsRow {
    const char* name;
    double m_R, m_T, R, beta_r, chi;
  };
  const IgsRow igs_rows[] = {
      {"IGS1", 5, 2, 1e-4, 0.5, 6},
      {"IGS2", 5, 2, 1e-4, 1, 2},
      {"IGS3", 5, 2, 1e-4, 1, 1},
      {"IGS4", 5, 2, 5e-5, 1, 1},
  };
  for (const auto& row : igs_rows) {
    SCOPED_TRACE(row.name);
    const auto igs = intergranular_strain_set(row.name);
    EXPECT_EQ(igs.m_R, row.m_R);
    EXPECT_EQ(igs.m_T, row.m_T);
    EXPECT_EQ(igs.R, row.R);
    EXPECT_EQ(igs.beta_r, row.beta_r);
    EXPECT_EQ(igs.chi, row.chi);
  }
  EXPECT_EQ(intergranular_strain_set("none").R, 0.0);
}

TEST(HypoplasticParameters, UnknownSetNameThrowsListingTheKnownNames) {
  const std::string message =
      expect_rejected([] { hypoplastic_set("orignal"); }, "set", "unknown hypoplastic set");
  EXPECT_NE(message.find("orignal"), std::string::npos) << message;
  for (const auto& name : hypoplastic_set_names())
    EXPECT_NE(message.find(name), std::string::npos) << name << " missing in: " << message;

  const std::string igs_message =
      expect_rejected([] { intergranular_strain_set("IGS9"); }, "igs", "unknown IGS set");
  EXPECT_NE(igs_message.find("IGS9"), std::string::npos) << igs_message;
  for (const auto& name : intergranular_strain_set_names())
    EXPECT_NE(igs_message.find(name), std::string::npos) << name << " missing in: " << igs_message;
}

TEST(HypoplasticParameters, InitialVoidRatioConventions) {
  const auto p = hypoplastic_set("original");
  for (double p0 : {0.0, 1.0e3, 1.0e5, 1.0e7, 3.0e7}) {
    for (double e0 : {0.567, 0.68, 0.9}) {
      const double expected = e0 * std::exp(-std::pow(3.0 * p0 / p.h_s, p.n));
      EXPECT_NEAR(initial_void_ratio(p, e0, VoidRatioConvention::at_zero_pressure, p0), expected,
                  1e-15 * expected);
      EXPECT_EQ(initial_void_ratio(p, e0, VoidRatioConvention::at_initial_stress, p0), e0);
    }
  }
  // A hand value: e0 = 0.68 at p0 = 10 MPa: (3e7/4e9)^0.42 = 0.128 -> e = 0.68 exp(-0.128).
  const double x = std::pow(7.5e-3, 0.42);
  EXPECT_NEAR(x, 0.12806, 1e-4);
  EXPECT_NEAR(initial_void_ratio(p, 0.68, VoidRatioConvention::at_zero_pressure, 1.0e7),
              0.68 * std::exp(-x), 1e-14);

  // Limit void ratios share the pressure function.
  const auto band = limit_void_ratios(p, 1.0e6);
  const double factor = std::exp(-std::pow(3.0e6 / p.h_s, p.n));
  EXPECT_DOUBLE_EQ(band.e_d, p.e_d0 * factor);
  EXPECT_DOUBLE_EQ(band.e_c, p.e_c0 * factor);
  EXPECT_DOUBLE_EQ(band.e_i, p.e_i0 * factor);

  EXPECT_EQ(parse_void_ratio_convention("initial-stress", "e0_convention"),
            VoidRatioConvention::at_initial_stress);
  EXPECT_EQ(parse_void_ratio_convention("zero-pressure", "e0_convention"),
            VoidRatioConvention::at_zero_pressure);
  EXPECT_EQ(to_string(VoidRatioConvention::at_zero_pressure), "zero-pressure");
  EXPECT_EQ(to_string(VoidRatioConvention::at_initial_stress), "initial-stress");
  expect_rejected([] { parse_void_ratio_convention("zero", "e0_convention"); }, "e0_convention",
                  "unknown convention");
}

TEST(HypoplasticParameters, IntegratorSchemeNames) {
  using S = IntegratorSettings::Scheme;
  EXPECT_EQ(parse_integrator_scheme("heun-euler", "scheme"), S::heun_euler);
  EXPECT_EQ(parse_integrator_scheme("bogacki-shampine", "scheme"), S::bogacki_shampine);
  EXPECT_EQ(to_string(S::heun_euler), "heun-euler");
  EXPECT_EQ(to_string(S::bogacki_shampine), "bogacki-shampine");
  expect_rejected([] { parse_integrator_scheme("rk45", "scheme"); }, "scheme", "unknown scheme");
}

}  // namespace
}  // namespace pilempm
