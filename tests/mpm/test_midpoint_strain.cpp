// The strain and spin increments on the increment's midpoint configuration (Hughes & Winget
// 1980), midpoint_strain.hpp: exact for a rigid rotation, the closed form 2(λ − 1)/(λ + 1) for a
// stretch λ, the general map equal to sym and skew of G (I + G/2)⁻¹, and the derivative that the
// Newton matrix chains with the stress's equal to the map's central differences.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "pilempm/mpm/quasi_static/midpoint_strain.hpp"

namespace pilempm::mpm::quasi_static::detail {
namespace {

constexpr double kRoot2 = 1.4142135623730951;

// The linear increments (G_xx, G_yy, h, (G_xy + G_yx)/√2, ½(G_yx − G_xy)) of a gradient G and a
// hoop increment h.
Vec5 linear_of(const Eigen::Matrix2d& g, double hoop) {
  Vec5 e;
  e << g(0, 0), g(1, 1), hoop, (g(0, 1) + g(1, 0)) / kRoot2, 0.5 * (g(1, 0) - g(0, 1));
  return e;
}

TEST(MidpointStrain, ARigidRotationHasNoStrainAndTheSpinOfItsCayleyForm) {
  for (const double angle : {1e-6, 0.01, 0.3, 1.0, 2.5}) {
    Eigen::Matrix2d rotation;
    rotation << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
    const Vec5 mid = midpoint_increments(linear_of(rotation - Eigen::Matrix2d::Identity(), 0.0));
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(mid[c], 0.0, 1e-15) << "angle " << angle;
    // The Hughes-Winget rotation of this spin, θ = 2 atan(w/2), is the rotation itself.
    EXPECT_NEAR(2.0 * std::atan(0.5 * mid[4]), angle, 1e-14);
    // The start configuration's strain, sym G, has cos θ − 1 in each normal component.
    EXPECT_NEAR(linear_of(rotation - Eigen::Matrix2d::Identity(), 0.0)[0], std::cos(angle) - 1.0,
                1e-15);
  }
}

TEST(MidpointStrain, AStretchGivesTwiceItsIncrementOverTheSumOfTheStretches) {
  for (const double stretch : {0.2, 0.9, 1.0, 1.05, 3.0}) {
    const double expected = 2.0 * (stretch - 1.0) / (stretch + 1.0);
    Eigen::Matrix2d g = Eigen::Matrix2d::Zero();
    g(0, 0) = stretch - 1.0;
    EXPECT_NEAR(midpoint_increments(linear_of(g, 0.0))[0], expected, 1e-15);
    g.setZero();
    g(1, 1) = stretch - 1.0;
    EXPECT_NEAR(midpoint_increments(linear_of(g, 0.0))[1], expected, 1e-15);
    EXPECT_NEAR(midpoint_increments(linear_of(Eigen::Matrix2d::Zero(), stretch - 1.0))[2], expected,
                1e-15);
    // Summed over n equal steps to the same stretch, it tends to ln λ with the error falling
    // as 1/n² (second order), where the start configuration's λ^(1/n) − 1 falls as 1/n.
    double error_midpoint[2], error_start[2];
    for (int k = 0; k < 2; ++k) {
      const int steps = 10 * (k + 1);
      const double step = std::pow(stretch, 1.0 / steps) - 1.0;
      error_midpoint[k] = steps * 2.0 * step / (step + 2.0) - std::log(stretch);
      error_start[k] = steps * step - std::log(stretch);
    }
    if (stretch == 1.0) continue;
    EXPECT_NEAR(error_midpoint[0] / error_midpoint[1], 4.0, 0.05) << "stretch " << stretch;
    EXPECT_NEAR(error_start[0] / error_start[1], 2.0, 0.1) << "stretch " << stretch;
  }
}

TEST(MidpointStrain, EqualsTheMidpointGradientsSymmetricAndSkewParts) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.4, 0.4);
  for (int trial = 0; trial < 200; ++trial) {
    Eigen::Matrix2d g;
    g << u(rng), u(rng), u(rng), u(rng);
    const double hoop = u(rng);
    const Eigen::Matrix2d l = g * (Eigen::Matrix2d::Identity() + 0.5 * g).inverse();
    const Vec5 linear = linear_of(g, hoop);
    ASSERT_TRUE(has_midpoint(linear));
    const Vec5 mid = midpoint_increments(linear);
    EXPECT_NEAR(mid[0], l(0, 0), 1e-14);
    EXPECT_NEAR(mid[1], l(1, 1), 1e-14);
    EXPECT_NEAR(mid[2], hoop / (1.0 + 0.5 * hoop), 1e-14);
    EXPECT_NEAR(mid[3], (l(0, 1) + l(1, 0)) / kRoot2, 1e-14);
    EXPECT_NEAR(mid[4], 0.5 * (l(1, 0) - l(0, 1)), 1e-14);
  }
}

TEST(MidpointStrain, ItsJacobianIsTheMapsDerivative) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.4, 0.4);
  double worst = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    Vec5 e;
    for (int c = 0; c < 5; ++c) e[c] = u(rng);
    Mat5 jacobian;
    midpoint_increments(e, &jacobian);
    const double h = 1e-6;
    for (int c = 0; c < 5; ++c) {
      Vec5 up = e, down = e;
      up[c] += h;
      down[c] -= h;
      const Vec5 difference = (midpoint_increments(up) - midpoint_increments(down)) / (2.0 * h);
      worst = std::max(worst, (difference - jacobian.col(c)).cwiseAbs().maxCoeff());
    }
  }
  EXPECT_LT(worst, 1e-8);
  // At zero increments the map is the identity.
  Mat5 at_zero;
  midpoint_increments(Vec5::Zero(), &at_zero);
  EXPECT_LT((at_zero - Mat5::Identity()).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(MidpointStrain, AnIncrementThatTurnsTheParticleInsideOutHasNoMidpoint) {
  Eigen::Matrix2d g = Eigen::Matrix2d::Zero();
  g(1, 1) = -2.5;  // λ = −1.5: inverted, and I + G/2 singular beyond −2
  EXPECT_FALSE(has_midpoint(linear_of(g, 0.0)));
  g(1, 1) = -0.9;
  EXPECT_TRUE(has_midpoint(linear_of(g, 0.0)));
  EXPECT_FALSE(has_midpoint(linear_of(Eigen::Matrix2d::Zero(), -2.0)));
}

}  // namespace
}  // namespace pilempm::mpm::quasi_static::detail
