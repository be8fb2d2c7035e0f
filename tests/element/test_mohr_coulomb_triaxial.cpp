// Mohr-Coulomb through the element driver (mixed stress and strain control): drained triaxial
// compression and extension limits in closed form, dilatancy at the limit, and the tension
// cut-off in uniaxial extension.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "../support/material_builders.hpp"
#include "pilempm/constitutive/mohr_coulomb/mohr_coulomb.hpp"
#include "pilempm/element/mixed_control_driver.hpp"

namespace pilempm {
namespace {

using Region = MohrCoulomb::ReturnRegion;

constexpr double kE = 50.0e6;
constexpr double kInf = std::numeric_limits<double>::infinity();

double deg(double d) {
  return d * kPi / 180.0;
}

// E = 50 MPa, nu = 0.3.
MohrCoulombParameters make(double c, double phi, double psi, double t = kInf) {
  return test_support::mohr_coulomb_parameters(kE, 0.3, c, phi, psi, t);
}

// The model is exact, so the stress control can be held far tighter than the driver's default.
MixedControlSettings tight_control() {
  MixedControlSettings settings;
  settings.stress_tolerance = 1e-3;
  settings.relative_tolerance = 1e-12;
  settings.max_iterations = 100;
  return settings;
}

// Drained triaxial test with constant cell pressure: component 0 axial (strain controlled),
// components 1 and 2 at the cell pressure, no shear strain. Returns the driver after n steps.
struct Triaxial {
  std::vector<double> axial_stress;  // tension positive
  std::vector<Vec6> strain;
  std::vector<double> plastic_shear;
};
Triaxial run_triaxial(const MohrCoulomb& model, double cell_pressure, double axial_step,
                      int steps) {
  MaterialState initial;
  initial.stress = diagonal6(-cell_pressure, -cell_pressure, -cell_pressure);
  initial.void_ratio = 0.6;
  MixedControlDriver driver(model, initial, tight_control());
  MixedIncrement inc;
  inc.stress_controlled = {false, true, true, false, false, false};
  inc.strain_increment[0] = axial_step;
  inc.stress_target = initial.stress;
  Triaxial out;
  for (int i = 0; i < steps; ++i) {
    driver.apply(inc);
    out.axial_stress.push_back(driver.state().stress[0]);
    out.strain.push_back(driver.strain());
    out.plastic_shear.push_back(MohrCoulomb::plastic_shear_strain(driver.state()));
    EXPECT_NEAR(driver.state().stress[1], -cell_pressure, 1e-2);
    EXPECT_NEAR(driver.state().stress[2], -cell_pressure, 1e-2);
  }
  return out;
}

// (c) The limit axial stress in triaxial compression is the closed form
// s1 = s3 (1 + sin phi)/(1 - sin phi) + 2 c cos phi / (1 - sin phi) (compression positive), and it
// is approached elastically with slope E and never overshot.
TEST(MohrCoulomb, TriaxialCompressionLimitMatchesClosedForm) {
  struct Case {
    double c, phi, psi, cell;
  };
  for (const Case& cs : {Case{0.0, 30.0, 0.0, 100e3}, Case{10e3, 35.0, 5.0, 50e3},
                         Case{25e3, 20.0, 20.0, 200e3}, Case{40e3, 0.0, 0.0, 100e3}}) {
    SCOPED_TRACE(testing::Message() << "c " << cs.c << " phi " << cs.phi << " cell " << cs.cell);
    const MohrCoulomb model(make(cs.c, cs.phi, cs.psi));
    const double s = std::sin(deg(cs.phi));
    const double limit =
        cs.cell * (1.0 + s) / (1.0 - s) + 2.0 * cs.c * std::cos(deg(cs.phi)) / (1.0 - s);
    const Triaxial tx = run_triaxial(model, cs.cell, -1e-4, 400);
    // First step elastic: d sigma_axial / d eps_axial = E at constant lateral stress.
    EXPECT_NEAR((tx.axial_stress[0] + cs.cell) / -1e-4, kE, 1e-6 * kE);
    double peak = 0.0;
    for (double a : tx.axial_stress) peak = std::max(peak, -a);
    EXPECT_NEAR(peak, limit, 1e-6 * limit);
    EXPECT_NEAR(-tx.axial_stress.back(), limit, 1e-6 * limit);
    EXPECT_GT(tx.plastic_shear.back(), 0.0);
  }
}

// (d) Triaxial extension (axial stress the minor compression) reaches the other edge:
// s_axial = s3 (1 - sin phi)/(1 + sin phi) - 2 c cos phi / (1 + sin phi) (compression positive).
TEST(MohrCoulomb, TriaxialExtensionLimitMatchesClosedForm) {
  struct Case {
    double c, phi, psi, cell;
  };
  for (const Case& cs :
       {Case{0.0, 30.0, 0.0, 100e3}, Case{10e3, 35.0, 10.0, 150e3}, Case{5e3, 25.0, 25.0, 200e3}}) {
    SCOPED_TRACE(testing::Message() << "c " << cs.c << " phi " << cs.phi << " cell " << cs.cell);
    const MohrCoulomb model(make(cs.c, cs.phi, cs.psi));
    const double s = std::sin(deg(cs.phi));
    const double limit =
        cs.cell * (1.0 - s) / (1.0 + s) - 2.0 * cs.c * std::cos(deg(cs.phi)) / (1.0 + s);
    const Triaxial tx = run_triaxial(model, cs.cell, 1e-4, 300);
    double lowest = kInf;
    for (double a : tx.axial_stress) lowest = std::min(lowest, -a);
    EXPECT_NEAR(lowest, limit, 1e-6 * cs.cell);
    EXPECT_NEAR(-tx.axial_stress.back(), limit, 1e-6 * cs.cell);
    // The closed form differs from the compression one: the edge is really the extension edge.
    const MohrCoulomb::PrincipalReturn ret =
        model.return_principal(Vec3(-limit, -cs.cell, -cs.cell) + Vec3(1e3, -1e2, -1e2));
    EXPECT_EQ(ret.region, Region::extension_edge);
  }
}

// (e) At the limit of triaxial compression all strain is plastic and the volumetric rate is the
// one of the potential: d eps_v / d eps_axial = 1 - m, m = (1 + sin psi)/(1 - sin psi); with
// psi = phi this is the associated value 1 - k, with psi = 0 there is no volume change.
TEST(MohrCoulomb, DilatancyAtTheLimitFollowsThePotential) {
  const double phi = 35.0;
  for (double psi : {phi, phi / 2.0, 0.0}) {
    SCOPED_TRACE(testing::Message() << "psi " << psi);
    const MohrCoulomb model(make(5e3, phi, psi));
    const Triaxial tx = run_triaxial(model, 100e3, -1e-4, 400);
    const Vec6 d_eps = tx.strain.back() - tx.strain[199];  // well past the limit
    const double rate = trace(d_eps) / d_eps[0];
    const double m = (1.0 + std::sin(deg(psi))) / (1.0 - std::sin(deg(psi)));
    EXPECT_NEAR(rate, 1.0 - m, 1e-6);
    if (psi == phi) {
      const double k = (1.0 + std::sin(deg(phi))) / (1.0 - std::sin(deg(phi)));
      EXPECT_NEAR(rate, 1.0 - k, 1e-6);
      EXPECT_LT(rate, -1.0);  // dilation: volume grows while the sample shortens
    }
    if (psi == 0.0) {
      EXPECT_NEAR(trace(d_eps), 0.0, 1e-9 * std::abs(d_eps[0]));
    }
    // Plastic shear strain grows by the triaxial shear strain of the (all plastic) increment.
    const double gained = tx.plastic_shear.back() - tx.plastic_shear[199];
    EXPECT_NEAR(gained, std::sqrt(2.0 / 3.0) * deviator(d_eps).norm(), 1e-6 * gained);
  }
}

// Tension cut-off in uniaxial extension from zero stress: the axial stress stops at t.
TEST(MohrCoulomb, UniaxialTensionStopsAtTheCutoff) {
  const MohrCoulomb model(make(30e3, 30, 10, 8e3));
  MaterialState initial;
  MixedControlDriver driver(model, initial, tight_control());
  MixedIncrement inc;
  inc.stress_controlled = {false, true, true, false, false, false};
  inc.strain_increment[0] = 2e-5;
  double top = -kInf;
  for (int i = 0; i < 100; ++i) {
    driver.apply(inc);
    top = std::max(top, driver.state().stress[0]);
  }
  EXPECT_NEAR(top, 8e3, 1e-6 * 8e3);
  EXPECT_NEAR(driver.state().stress[0], 8e3, 1e-6 * 8e3);
  EXPECT_NEAR(model.tension_function(driver.state().stress), 0.0, 1e-3);
}

}  // namespace
}  // namespace pilempm
