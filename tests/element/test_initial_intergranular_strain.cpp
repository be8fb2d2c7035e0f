// The initial intergranular strain of element tests: fully mobilised along the first strain
// increment, and an explicit tensor.
#include <gtest/gtest.h>

#include <cmath>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/element/element_tests.hpp"

namespace {

using namespace pilempm;

OedometerTest oedometer() {
  OedometerTest t;
  t.sigma_v0 = 10e3;
  t.K0 = 0.485;
  t.sigma_v_targets = {400e3};
  t.steps_per_segment = 100;
  return t;
}

InitialCondition initial(InitialCondition::Igs igs) {
  InitialCondition i;
  i.e0 = 0.7;
  i.igs = igs;
  return i;
}

// With delta fully mobilised (rho = 1) along the strain rate D, the intergranular-strain model's
// stiffness is m_T L + (1 - m_T) L:dd + N d, which applied to D is L:D + N ||D||: the basic
// model's response (Niemunis & Herle 1997). So an oedometer started with delta along its first
// (axial) increment takes that increment exactly as the model without intergranular strain,
// while the isotropic start ("compression") makes it stiffer. Equal to the integrator's accuracy:
// the run with intergranular strain takes shorter sub-steps (its stability limit, R / ||Δε||),
// so the two integrate the same rates along different sub-steps (measured: 1.0e-5 apart).
TEST(InitialIntergranularStrain, FirstIncrementStartGivesTheBasicModelsFirstStep) {
  const HypoplasticParameters set = hypoplastic_set("original");
  const Hypoplastic with_igs(set, intergranular_strain_set("IGS3"));
  const Hypoplastic basic(set);
  const auto first_strain = [](const ConstitutiveModel& model, InitialCondition::Igs igs) {
    return run_element_test(model, oedometer(), initial(igs)).curve[1].axial_strain;
  };
  const double along = first_strain(with_igs, InitialCondition::Igs::first_increment);
  const double reference = first_strain(basic, InitialCondition::Igs::zero);
  const double isotropic = first_strain(with_igs, InitialCondition::Igs::compression);
  EXPECT_NEAR(along, reference, 1e-4 * reference);
  EXPECT_LT(isotropic, 0.9 * reference);  // stiffer: the path turns away from delta
  // The intergranular strain stays fully mobilised along the loading.
  const ElementResult r =
      run_element_test(with_igs, oedometer(), initial(InitialCondition::Igs::first_increment));
  EXPECT_NEAR(r.curve[1].igs_ratio, 1.0, 1e-9);
}

TEST(InitialIntergranularStrain, ExplicitTensorEqualToTheIsotropicStartGivesTheSameCurve) {
  const Hypoplastic model(hypoplastic_set("original"), intergranular_strain_set("IGS3"));
  InitialCondition tensor = initial(InitialCondition::Igs::tensor);
  tensor.igs_tensor = -1e-4 / kSqrt3 * identity6();
  const ElementResult a = run_element_test(model, oedometer(), tensor);
  const ElementResult b =
      run_element_test(model, oedometer(), initial(InitialCondition::Igs::compression));
  ASSERT_EQ(a.curve.size(), b.curve.size());
  EXPECT_DOUBLE_EQ(a.curve.back().void_ratio, b.curve.back().void_ratio);
  // A tensor longer than R is impossible.
  tensor.igs_tensor = diagonal6(-2e-4, 0.0, 0.0);
  EXPECT_THROW(run_element_test(model, oedometer(), tensor), InvalidValue);
}

TEST(InitialIntergranularStrain, FirstIncrementOfATriaxialTestIsFoundAsAFixedPoint) {
  // Under mixed control the first increment's direction depends on the stiffness, which depends
  // on delta: the start must be the fixed point, delta parallel to the increment it produces.
  const Hypoplastic model(hypoplastic_set("original"), intergranular_strain_set("IGS3"));
  DrainedTriaxialTest t;
  t.sigma3 = 100e3;
  t.axial_strain = 0.01;
  t.steps = 100;
  const ElementResult r =
      run_element_test(model, t, initial(InitialCondition::Igs::first_increment));
  const Hypoplastic basic(hypoplastic_set("original"));
  const ElementResult b = run_element_test(basic, t, initial(InitialCondition::Igs::zero));
  // Along its own direction the first step is the basic model's: same radial strain.
  EXPECT_NEAR(r.curve[1].radial_strain, b.curve[1].radial_strain,
              1e-5 * std::abs(b.curve[1].radial_strain));
  EXPECT_NEAR(r.curve[1].q, b.curve[1].q, 1e-5 * b.curve[1].q);
}

}  // namespace
