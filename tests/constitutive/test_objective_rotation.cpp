// Hughes-Winget rotation of the state by a spin increment.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/constitutive/objective_rotation.hpp"

namespace pilempm {
namespace {

Mat3 random_spin(std::mt19937& rng, double size) {
  std::uniform_real_distribution<double> u(-size, size);
  const double a = u(rng), b = u(rng), c = u(rng);
  Mat3 w;
  w << 0.0, -c, b, c, 0.0, -a, -b, a, 0.0;
  return w;
}

TEST(ObjectiveRotation, HughesWingetRotationIsProperOrthogonal) {
  std::mt19937 rng(3);
  for (double size : {1e-6, 1e-2, 0.5, 3.0}) {
    for (int i = 0; i < 50; ++i) {
      const Mat3 r = hughes_winget_rotation(random_spin(rng, size));
      EXPECT_LE((r.transpose() * r - Mat3::Identity()).norm(), 1e-13);
      EXPECT_NEAR(r.determinant(), 1.0, 1e-13);
    }
  }
  EXPECT_LE((hughes_winget_rotation(Mat3::Zero()) - Mat3::Identity()).norm(), 0.0);
}

TEST(ObjectiveRotation, RotatingAStatePreservesInvariants) {
  const Hypoplastic model(hypoplastic_set("original"), intergranular_strain_set("IGS3"));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 100; ++i) {
    MaterialState state;
    for (int j = 0; j < 6; ++j) {
      state.stress[j] = 1e5 * u(rng);
      Hypoplastic::intergranular_strain(state)[j] = 1e-4 * u(rng);
    }
    state.void_ratio = 0.7;
    const MaterialState before = state;
    rotate_state(state, random_spin(rng, 0.3), model.history_variables());
    EXPECT_NEAR(trace(state.stress), trace(before.stress), 1e-9);
    EXPECT_NEAR(state.stress.norm(), before.stress.norm(), 1e-9);
    EXPECT_NEAR(determinant(state.stress), determinant(before.stress),
                1e-12 * std::pow(before.stress.norm(), 3));
    EXPECT_LE((principal_values(state.stress) - principal_values(before.stress)).norm(), 1e-9);
    EXPECT_NEAR(Hypoplastic::intergranular_strain(state).norm(),
                Hypoplastic::intergranular_strain(before).norm(), 1e-18);
    EXPECT_NEAR(trace(Hypoplastic::intergranular_strain(state)),
                trace(Hypoplastic::intergranular_strain(before)), 1e-18);
    EXPECT_EQ(state.void_ratio, before.void_ratio);
  }
}

// A spin w about z (W12 = -w, W21 = w) turns x toward y by the Cayley angle 2 atan(w/2): a uniaxial
// x stress s becomes s (cos^2, sin^2, cos sin) in (xx, yy, xy).
TEST(ObjectiveRotation, SpinAboutZTurnsUniaxialStressTowardY) {
  for (double w : {1e-3, 0.1, 0.7, 2.0}) {
    Mat3 spin = Mat3::Zero();
    spin(0, 1) = -w;
    spin(1, 0) = w;
    MaterialState state;
    const double s = -2e5;
    state.stress = diagonal6(s, 0.0, 0.0);
    rotate_state(state, spin, {});
    const double angle = 2.0 * std::atan(w / 2.0);
    const Mat3 m = to_matrix(state.stress);
    EXPECT_NEAR(m(0, 0), s * std::cos(angle) * std::cos(angle), 1e-9) << w;
    EXPECT_NEAR(m(1, 1), s * std::sin(angle) * std::sin(angle), 1e-9) << w;
    EXPECT_NEAR(m(0, 1), s * std::cos(angle) * std::sin(angle), 1e-9) << w;
    EXPECT_NEAR(m(2, 2), 0.0, 1e-9);
    EXPECT_NEAR(m(0, 2), 0.0, 1e-9);
    EXPECT_NEAR(m(1, 2), 0.0, 1e-9);
    // The rotation matrix itself: R e_x = (cos, sin, 0).
    const Mat3 r = hughes_winget_rotation(spin);
    EXPECT_NEAR(r(0, 0), std::cos(angle), 1e-14);
    EXPECT_NEAR(r(1, 0), std::sin(angle), 1e-14);
  }
}

}  // namespace
}  // namespace pilempm
