// Element-test results converge as the increment size shrinks (issue: constitutive library).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/element/element_tests.hpp"

namespace pilempm {
namespace {

TEST(IncrementConvergence, DrainedTriaxialPeakConvergesWithIncrementSize) {
  // Tight tolerance, so that what is left is the dependence on the increment size (the strain
  // direction of the driver is fixed within an increment, and the stress-controlled components
  // are only in equilibrium at the increments' ends).
  IntegratorSettings tight;
  tight.tolerance = 1e-7;
  const Hypoplastic model(hypoplastic_set("original"), intergranular_strain_set("IGS3"), tight);
  InitialCondition initial;
  initial.e0 = 0.60;
  DrainedTriaxialTest test;
  test.sigma3 = 100e3;
  test.axial_strain = 0.1;
  std::vector<double> peak_q, final_e;
  for (int steps : {5, 10, 20, 40, 80}) {
    test.steps = steps;
    const ElementResult r = run_element_test(model, test, initial);
    peak_q.push_back(r.summary.peak_q);
    final_e.push_back(r.summary.final.void_ratio);
  }
  // Measured: peak q = 387.5, 407.7, 416.1, 417.6, 418.1 kPa for 5 ... 80 increments; the
  // successive differences shrink (about first order), the finest two agree within 0.2 %, and
  // the final void ratio is within 1e-4 of the finest at every increment size.
  for (std::size_t i = 2; i < peak_q.size(); ++i)
    EXPECT_LT(std::abs(peak_q[i] - peak_q[i - 1]), std::abs(peak_q[i - 1] - peak_q[i - 2]))
        << "at refinement " << i;
  EXPECT_LT(std::abs(peak_q[4] / peak_q[3] - 1.0), 2e-3);
  for (double e : final_e) EXPECT_NEAR(e, final_e.back(), 1e-4);
}

}  // namespace
}  // namespace pilempm
