// The stress-dependent alpha (and Rohe void ratios) option of the hypoplastic model (docs/study.md
// §5).
#include <gtest/gtest.h>

#include <cmath>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/constitutive/hypoplastic/rohe_void_ratios.hpp"
#include "pilempm/core/error.hpp"

namespace pilempm {
namespace {

HypoplasticParameters stress_dependent_original() {
  HypoplasticParameters p = hypoplastic_set("original");
  p.stress_dependence.alpha_varies = true;
  return p;
}

MaterialState isotropic_state(double p, double e) {
  MaterialState s;
  s.stress = -p * identity6();
  s.void_ratio = e;
  return s;
}

Vec6 shear_direction() {
  Vec6 d;
  d << -1.0, 0.4, 0.4, 0.0, 0.0, 0.0;
  return d;
}

TEST(StressDependentAlpha, LawHitsItsEndValuesAndIsSmooth) {
  const StressDependence law = stress_dependent_original().stress_dependence;
  EXPECT_DOUBLE_EQ(law.alpha(1e3), law.alpha_low);
  EXPECT_DOUBLE_EQ(law.alpha(law.p_low), law.alpha_low);
  EXPECT_DOUBLE_EQ(law.alpha(law.p_high), law.alpha_high);
  EXPECT_DOUBLE_EQ(law.alpha(1e9), law.alpha_high);
  // Monotonic between, with a continuous slope (d alpha / d ln p -> 0 at both ends).
  double previous = law.alpha_low;
  for (double p = law.p_low; p <= law.p_high; p *= 1.01) {
    const double a = law.alpha(p);
    EXPECT_LE(a, previous + 1e-15);
    previous = a;
  }
  const double h = 1e-4;
  for (double p_end : {law.p_low, law.p_high}) {
    const double slope =
        (law.alpha(p_end * std::exp(h)) - law.alpha(p_end * std::exp(-h))) / (2.0 * h);
    EXPECT_LT(std::abs(slope), 1e-3) << "kink at p = " << p_end;
  }
  // Halfway in ln p the smoothstep gives the mean of the end values.
  EXPECT_NEAR(law.alpha(std::sqrt(law.p_low * law.p_high)), 0.5 * (law.alpha_low + law.alpha_high),
              1e-12);
}

TEST(StressDependentAlpha, SwitchedOffIsExactlyTheBasicModel) {
  HypoplasticParameters off = hypoplastic_set("original");
  off.stress_dependence.alpha_low = 0.5;  // ignored while alpha_varies is false
  off.stress_dependence.alpha_high = 0.0;
  const Hypoplastic basic(hypoplastic_set("original"), intergranular_strain_set("IGS3"));
  const Hypoplastic with_off_option(off, intergranular_strain_set("IGS3"));
  EXPECT_EQ(with_off_option.name(), "hypoplastic+IGS");
  MaterialState a = isotropic_state(150e3, 0.7), b = a;
  for (int i = 0; i < 200; ++i) {
    const Vec6 d = (i / 50) % 2 ? Vec6(-1e-4 * shear_direction()) : Vec6(1e-4 * shear_direction());
    basic.update(a, d);
    with_off_option.update(b, d);
  }
  EXPECT_EQ(a.stress, b.stress);  // bitwise
  EXPECT_EQ(a.void_ratio, b.void_ratio);
}

TEST(StressDependentAlpha, ConstantLawEqualsTheBasicModelThroughTheOptionCode) {
  // alpha_low = alpha_high = alpha goes through the stress-dependent code path but must give
  // the basic model to round-off.
  HypoplasticParameters flat = stress_dependent_original();
  flat.stress_dependence.alpha_low = flat.alpha;
  flat.stress_dependence.alpha_high = flat.alpha;
  const Hypoplastic basic(hypoplastic_set("original"));
  const Hypoplastic option(flat);
  EXPECT_EQ(option.name(), "hypoplastic+stress-dependent");
  for (double p : {10e3, 300e3, 2e6, 30e6}) {
    const MaterialState s = isotropic_state(p, 0.65);
    const Vec6 r1 = basic.rate(s, shear_direction()).stress;
    const Vec6 r2 = option.rate(s, shear_direction()).stress;
    EXPECT_LT((r1 - r2).norm(), 1e-13 * r1.norm()) << "p = " << p;
  }
}

TEST(StressDependentAlpha, StiffnessIsContinuousAlongIsotropicCompression) {
  // Along an isotropic compression through the whole transition (50 kPa to 20 MPa, p x 1.01 per
  // increment) the stress rate for a fixed shear direction changes per increment by no more
  // than the basic model's own change plus 0.1 %: alpha(p) adds no jump.
  const Hypoplastic basic(hypoplastic_set("original"));
  const Hypoplastic option(stress_dependent_original());
  const HypoplasticParameters& params = basic.parameters();
  double worst_basic = 0.0, worst_option = 0.0;
  Vec6 last_basic = Vec6::Zero(), last_option = Vec6::Zero();
  for (double p = 50e3; p < 20e6; p *= 1.01) {
    const double e = 0.9 * limit_void_ratios(params, p).e_c;  // a fixed density index
    const MaterialState s = isotropic_state(p, e);
    const Vec6 rb = basic.rate(s, shear_direction()).stress / p;
    const Vec6 ro = option.rate(s, shear_direction()).stress / p;
    if (last_basic.norm() > 0.0) {
      worst_basic = std::max(worst_basic, (rb - last_basic).norm() / rb.norm());
      worst_option = std::max(worst_option, (ro - last_option).norm() / ro.norm());
    }
    last_basic = rb;
    last_option = ro;
  }
  EXPECT_GT(worst_basic, 0.0);
  EXPECT_LT(worst_option, worst_basic + 1e-3);
}

TEST(StressDependentAlpha, RoheVoidRatiosReplaceTheConstants) {
  HypoplasticParameters p = stress_dependent_original();
  p.stress_dependence.rohe_void_ratios = true;
  const auto r = p.reference_at(10e6);
  const auto rohe = rohe_reference_void_ratios(10e6);
  EXPECT_DOUBLE_EQ(r.e_c0, rohe.e_c0);
  EXPECT_DOUBLE_EQ(r.e_d0, rohe.e_d0);
  EXPECT_DOUBLE_EQ(r.e_i0, rohe.e_i0);
  EXPECT_DOUBLE_EQ(r.alpha, p.stress_dependence.alpha_high);
  const LimitVoidRatios band = limit_void_ratios(p, 10e6);
  const double bauer = std::exp(-std::pow(3.0 * 10e6 / p.h_s, p.n));
  EXPECT_NEAR(band.e_c, rohe.e_c0 * bauer, 1e-14);
}

TEST(StressDependentAlpha, InvalidLawIsRejectedWithItsKey) {
  HypoplasticParameters p = stress_dependent_original();
  p.stress_dependence.p_high = p.stress_dependence.p_low;
  try {
    p.validate();
    FAIL() << "expected InvalidValue";
  } catch (const InvalidValue& e) {
    EXPECT_EQ(e.key(), "p_high_Pa");
  }
  p = stress_dependent_original();
  p.stress_dependence.alpha_high = -0.1;
  EXPECT_THROW(p.validate(), InvalidValue);
  p = stress_dependent_original();
  p.stress_dependence.alpha_low = 10.0;  // f_b's denominator would turn negative
  try {
    p.validate();
    FAIL() << "expected InvalidValue";
  } catch (const InvalidValue& e) {
    EXPECT_EQ(e.key(), "alpha_low");
  }
}

}  // namespace
}  // namespace pilempm
