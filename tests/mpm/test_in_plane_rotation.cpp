// The in-plane Jaumann rotation used by the solver equals the general Hughes-Winget rotation of
// the constitutive library (rotate_state) for a spin about z.
#include <gtest/gtest.h>

#include <random>

#include "pilempm/constitutive/objective_rotation.hpp"
#include "pilempm/mpm/in_plane_rotation.hpp"

namespace pilempm::mpm {
namespace {

// A history like hypoplasticity's intergranular strain (a tensor) next to a scalar like
// Mohr-Coulomb's plastic shear strain.
constexpr HistoryVariable kHistory[] = {{"intergranular_strain", 0, 6, true},
                                        {"plastic_shear_strain", 6, 1, false}};

Vec6 tensor(const MaterialState& state) {
  return Eigen::Map<const Vec6>(state.history.data());
}

TEST(InPlaneRotation, EqualsRotateStateForASpinAboutZ) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double size : {1e-8, 1e-3, 0.1, 1.0, 4.0}) {
    for (int trial = 0; trial < 50; ++trial) {
      MaterialState state;
      for (int j = 0; j < 6; ++j) {
        state.stress[j] = 1e5 * u(rng);
        state.history[static_cast<std::size_t>(j)] = 1e-4 * u(rng);
      }
      state.void_ratio = 0.7;
      state.history[6] = 0.01;
      const double w = size * u(rng);
      Mat3 spin = Mat3::Zero();
      spin(1, 0) = w;
      spin(0, 1) = -w;
      MaterialState general = state, in_plane = state;
      rotate_state(general, spin, kHistory);
      rotate_state_about_z(in_plane, w, kHistory);
      EXPECT_LE((general.stress - in_plane.stress).norm(), 1e-15 * 1e5 * 6) << w;
      EXPECT_LE((tensor(general) - tensor(in_plane)).norm(), 1e-15 * 1e-4 * 6) << w;
      EXPECT_EQ(in_plane.void_ratio, state.void_ratio);
      EXPECT_EQ(in_plane.history[6], state.history[6]);
    }
  }
}

// The turned tensor's derivative with respect to the spin increment (the Newton matrix's spin
// terms) equals central differences of the turn, at spins from round-off size to 4.
TEST(InPlaneRotation, TheTurnsDerivativeEqualsItsCentralDifference) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double h = 1e-6;
  for (double size : {1e-8, 1e-3, 0.1, 1.0, 4.0}) {
    for (int trial = 0; trial < 20; ++trial) {
      MaterialState state;
      for (int j = 0; j < 6; ++j) state.stress[j] = 1e5 * u(rng);
      const double w = size * u(rng);
      MaterialState at = state, plus = state, minus = state;
      rotate_state_about_z(at, w, kHistory);
      rotate_state_about_z(plus, w + h, kHistory);
      rotate_state_about_z(minus, w - h, kHistory);
      const Vec6 difference = (plus.stress - minus.stress) / (2.0 * h);
      EXPECT_LE((rotation_derivative_about_z(at.stress, w) - difference).norm(), 1e-8 * 1e5 * 6)
          << w;
    }
  }
}

}  // namespace
}  // namespace pilempm::mpm
