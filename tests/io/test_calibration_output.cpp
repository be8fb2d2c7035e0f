// The parameters.toml that `pilempm calibrate` writes (io/calibration_output.hpp) is a
// [[material]] that an element case accepts unchanged (docs/calibration.md).
#include <gtest/gtest.h>

#include "../support/calibration_builders.hpp"
#include "pilempm/io/calibration_output.hpp"
#include "pilempm/io/element_case.hpp"

namespace {

using namespace pilempm;
using namespace pilempm::calibration;
using test_support::problem_of;
using test_support::truth_of;

// The parameters.toml of a fit is a [[material]] that an element case accepts unchanged, and
// the element test with it gives the fitted curve.
TEST(CalibrationOutput, ParametersTomlRunsUnchangedInAnElementTest) {
  CalibrationProblem p = problem_of("original", 0.60, 0.80, 40);
  p.material_name = "fitted-sand";
  ParameterSet s = truth_of("original");
  s.hypoplastic.phi_c_deg = 32.25;
  s.hypoplastic.alpha = 0.1375;
  const std::string material = parameters_toml(p, s, "test");
  const std::string text = material +
                           "\n[[test]]\nname = \"tx\"\ntype = \"triaxial\"\nset = \"fitted-sand\"\n"
                           "e0 = 0.6\ne0_at = \"initial-stress\"\nsigma3_kPa = 100\n"
                           "axial_strain = 0.2\nsteps = 40\n";
  const ElementCaseFile file = parse_element_case(text, "parameters.toml + test");
  ASSERT_EQ(file.tests.size(), 1u);
  const ElementCase& c = file.tests.front();
  EXPECT_DOUBLE_EQ(c.material.hypoplastic().phi_c_deg, 32.25);
  EXPECT_DOUBLE_EQ(c.material.hypoplastic().alpha, 0.1375);
  ASSERT_TRUE(c.igs);
  EXPECT_DOUBLE_EQ(c.igs->parameters.R, 1e-4);
  const ElementResult from_file = run_element_test(*c.model, c.test, c.initial);
  const ElementResult direct =
      run_lab_test(p.tests[3], make_hypoplastic(s, c.integrator));  // tx-dense-100
  ASSERT_EQ(from_file.curve.size(), direct.curve.size());
  EXPECT_NEAR(from_file.curve.back().q, direct.curve.back().q, 1e-6 * direct.curve.back().q);
}

}  // namespace
