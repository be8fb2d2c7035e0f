// The mixed-control driver and the element-test types, checked against linear elasticity (where
// every test has a closed form) and against the definitions of the summary quantities.
#include <gtest/gtest.h>

#include <cmath>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/element/element_tests.hpp"
#include "pilempm/element/mixed_control_driver.hpp"

namespace pilempm {
namespace {

const ElasticParameters kElastic{50e6, 0.3};

TEST(MixedControlDriver, StressControlledComponentsReachTheirTargets) {
  const LinearElastic model(kElastic);
  MaterialState start;
  start.stress = -100e3 * identity6();
  start.void_ratio = 0.7;
  MixedControlDriver driver(model, start);
  MixedIncrement inc;
  inc.stress_controlled = {false, true, true, true, false, false};
  inc.strain_increment[k11] = -1e-3;
  inc.stress_target << 0.0, -80e3, -120e3, 5e3, 0.0, 0.0;
  driver.apply(inc);
  EXPECT_NEAR(driver.state().stress[k22], -80e3, 1e-2);
  EXPECT_NEAR(driver.state().stress[k33], -120e3, 1e-2);
  EXPECT_NEAR(driver.state().stress[k23], 5e3, 1e-2);
  EXPECT_DOUBLE_EQ(driver.strain()[k11], -1e-3);
  EXPECT_DOUBLE_EQ(driver.strain()[k13], 0.0);
}

TEST(ElementTests, ElasticOedometerGivesKzeroAndConstrainedModulus) {
  const LinearElastic model(kElastic);
  OedometerTest oed;
  oed.sigma_v0 = 100e3;
  oed.K0 = kElastic.poisson_ratio / (1.0 - kElastic.poisson_ratio);
  oed.sigma_v_targets = {300e3};
  oed.steps_per_segment = 10;
  InitialCondition initial;
  initial.e0 = 0.7;
  const ElementResult r = run_element_test(model, oed, initial);
  const CurvePoint& end = r.summary.final;
  const double constrained = kElastic.bulk_modulus() + 4.0 / 3.0 * kElastic.shear_modulus();
  EXPECT_NEAR(end.axial_strain, 200e3 / constrained, 1e-9);
  EXPECT_NEAR(end.radial_strain, 0.0, 1e-15);
  // The lateral stress follows K0 = nu / (1 - nu) in elastic 1D compression.
  EXPECT_NEAR(end.radial_stress / end.axial_stress, oed.K0, 1e-6);
  ASSERT_EQ(r.curve.size(), 11u);
}

TEST(ElementTests, ElasticDrainedTriaxialGivesYoungsModulusAndPoisson) {
  const LinearElastic model(kElastic);
  DrainedTriaxialTest tx;
  tx.sigma3 = 100e3;
  tx.axial_strain = 0.01;
  tx.steps = 20;
  const ElementResult r = run_element_test(model, tx, InitialCondition{});
  const CurvePoint& end = r.summary.final;
  EXPECT_NEAR(end.q / end.axial_strain, kElastic.young_modulus, 1e-3 * kElastic.young_modulus);
  EXPECT_NEAR(end.volumetric_strain / end.axial_strain, 1.0 - 2.0 * kElastic.poisson_ratio, 1e-6);
  EXPECT_NEAR(end.radial_stress, 100e3, 1.0);
  EXPECT_TRUE(r.summary.peak_at_end);  // elastic: q grows to the end, no peak
}

TEST(ElementTests, UndrainedTriaxialKeepsVolumeAndVoidRatio) {
  const Hypoplastic model(hypoplastic_set("original"), intergranular_strain_set("IGS3"));
  UndrainedTriaxialTest ux;
  ux.p0 = 200e3;
  ux.axial_strain = 0.05;
  ux.steps = 500;
  // e_c(200 kPa) = 0.906 for the original set: e = 0.89 is loose (contractant), so the mean
  // stress falls under undrained shear; e = 0.60 is dense (dilatant), so it rises.
  InitialCondition initial;
  initial.e0 = 0.89;
  const ElementResult loose = run_element_test(model, ux, initial);
  EXPECT_NEAR(loose.summary.final.volumetric_strain, 0.0, 1e-14);
  EXPECT_NEAR(loose.summary.final.void_ratio, 0.89, 1e-12);
  EXPECT_LT(loose.summary.final.p, 0.8 * ux.p0);
  initial.e0 = 0.60;
  const ElementResult dense = run_element_test(model, ux, initial);
  EXPECT_NEAR(dense.summary.final.void_ratio, 0.60, 1e-12);
  EXPECT_GT(dense.summary.final.p, 1.5 * ux.p0);
}

TEST(ElementTests, InitialStateFollowsTheVoidRatioConvention) {
  const Hypoplastic model(hypoplastic_set("original"), intergranular_strain_set("IGS3"));
  InitialCondition initial;
  initial.e0 = 0.8;
  initial.e0_at = VoidRatioConvention::at_zero_pressure;
  const Vec6 stress = -1e6 * identity6();
  const MaterialState s = initial_state(model, stress, initial);
  const auto& p = model.parameters();
  EXPECT_NEAR(s.void_ratio, 0.8 * std::exp(-std::pow(3.0 * 1e6 / p.h_s, p.n)), 1e-14);
  EXPECT_NEAR(Hypoplastic::intergranular_strain(s).norm(), model.intergranular().R, 1e-18);
  EXPECT_LT(trace(Hypoplastic::intergranular_strain(s)), 0.0);  // mobilised by compression
  initial.e0_at = VoidRatioConvention::at_initial_stress;
  initial.igs = InitialCondition::Igs::zero;
  const MaterialState t = initial_state(model, stress, initial);
  EXPECT_DOUBLE_EQ(t.void_ratio, 0.8);
  EXPECT_DOUBLE_EQ(Hypoplastic::intergranular_strain(t).norm(), 0.0);
}

TEST(ElementTests, SummaryFindsPeakAndDilatancy) {
  // A synthetic curve: q peaks at the third point, with eps_v falling 0.5 per unit eps_1 there.
  std::vector<CurvePoint> curve(5);
  const double q[] = {0, 100, 150, 120, 110};
  for (int i = 0; i < 5; ++i) {
    curve[i] = CurvePoint{};
    curve[i].axial_strain = 0.01 * i;
    curve[i].volumetric_strain = -0.005 * i;
    curve[i].q = q[i];
    curve[i].phi_mobilised_deg = q[i] / 10.0;
  }
  const ElementSummary s = summarise(curve);
  EXPECT_DOUBLE_EQ(s.peak_q, 150.0);
  EXPECT_DOUBLE_EQ(s.axial_strain_at_peak, 0.02);
  EXPECT_DOUBLE_EQ(s.phi_at_peak_deg, 15.0);
  EXPECT_NEAR(s.dilatancy_ratio_at_peak, -0.5, 1e-12);
  EXPECT_NEAR(std::sin(s.psi_at_peak_deg * kPi / 180.0), 0.5 / 2.5, 1e-12);
  EXPECT_FALSE(s.peak_at_end);
}

TEST(ElementTests, PlateauPeakIsWhereThePlateauStarts) {
  // Perfect plasticity: q stays at its limit; the dilatancy comes from the plastic increment.
  std::vector<CurvePoint> curve(5);
  const double q[] = {0, 100, 150, 150, 150};
  const double eps_v[] = {0, 0.003, 0.006, 0.006, 0.006};  // elastic compaction, then psi = 0
  for (int i = 0; i < 5; ++i) {
    curve[i] = CurvePoint{};
    curve[i].axial_strain = 0.01 * i;
    curve[i].volumetric_strain = eps_v[i];
    curve[i].q = q[i];
  }
  const ElementSummary s = summarise(curve);
  EXPECT_DOUBLE_EQ(s.axial_strain_at_peak, 0.02);
  EXPECT_FALSE(s.peak_at_end);
  EXPECT_DOUBLE_EQ(s.psi_at_peak_deg, 0.0);
}

TEST(ElementTests, DilatancyAngleMatchesBoltonsForm) {
  // Bolton (1986) with Schanz & Vermeer: (-d eps_v/d eps_1) = 0.3 I_R gives
  // sin psi = 0.3 I_R / (2 + 0.3 I_R); for I_R = 2.596 that is psi = 16.277 deg (docs/study.md §3).
  EXPECT_NEAR(dilatancy_angle_deg(-0.3 * 2.596), 16.277, 1e-3);
  EXPECT_NEAR(dilatancy_angle_deg(0.0), 0.0, 1e-15);
}

TEST(ElementTests, MobilisedFrictionAngleOfAKnownState) {
  // sigma_1 = 3 sigma_3 gives sin phi = 2/4, phi = 30 deg.
  EXPECT_NEAR(mobilised_friction_angle_deg(-diagonal6(300e3, 100e3, 100e3)), 30.0, 1e-10);
  EXPECT_NEAR(mobilised_friction_angle_deg(-diagonal6(100e3, 300e3, 100e3)), 30.0, 1e-10);
}

TEST(ElementTests, ImpossibleSettingsAreRejectedWithTheirKey) {
  const LinearElastic model(kElastic);
  DrainedTriaxialTest tx;
  tx.sigma3 = -5.0;
  try {
    run_element_test(model, tx, InitialCondition{});
    FAIL() << "expected InvalidValue";
  } catch (const InvalidValue& e) {
    EXPECT_EQ(e.key(), "sigma3_kPa");
  }
  OedometerTest oed;
  oed.sigma_v_targets.clear();
  EXPECT_THROW(validate(oed), InvalidValue);
  IsotropicCompressionTest iso;
  iso.steps = 0;
  EXPECT_THROW(validate(iso), InvalidValue);
}

TEST(ElementTests, CyclicOedometerWithIntergranularStrainRatchetsLess) {
  // Niemunis & Herle (1997): the intergranular strain reduces the accumulation of strain in
  // small load cycles that the basic model overpredicts.
  OedometerTest oed;
  oed.sigma_v0 = 100e3;
  oed.sigma_v_targets = {200e3, 150e3, 200e3, 150e3, 200e3};
  oed.steps_per_segment = 100;
  InitialCondition initial;
  initial.e0 = 0.7;
  const Hypoplastic basic(hypoplastic_set("original"), intergranular_strain_set("none"));
  const Hypoplastic igs(hypoplastic_set("original"), intergranular_strain_set("IGS3"));
  auto ratchet = [&](const ConstitutiveModel& model) {
    const ElementResult r = run_element_test(model, oed, initial);
    const std::size_t first_peak = static_cast<std::size_t>(oed.steps_per_segment);
    return r.curve.back().axial_strain - r.curve[first_peak].axial_strain;
  };
  const double basic_ratchet = ratchet(basic);
  const double igs_ratchet = ratchet(igs);
  EXPECT_GT(basic_ratchet, 0.0);
  EXPECT_LT(igs_ratchet, 0.5 * basic_ratchet);
}

}  // namespace
}  // namespace pilempm
