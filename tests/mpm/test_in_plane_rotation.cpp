// The in-plane Jaumann rotation used by the solver equals the general Hughes-Winget rotation of
// the constitutive library (rotate_state) for a spin about z.
#include <gtest/gtest.h>

#include <random>

#include "pilempm/constitutive/objective_rotation.hpp"
#include "pilempm/mpm/in_plane_rotation.hpp"

namespace pilempm::mpm {
namespace {

TEST(InPlaneRotation, EqualsRotateStateForASpinAboutZ) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double size : {1e-8, 1e-3, 0.1, 1.0, 4.0}) {
    for (int trial = 0; trial < 50; ++trial) {
      MaterialState state;
      for (int j = 0; j < 6; ++j) {
        state.stress[j] = 1e5 * u(rng);
        state.intergranular_strain[j] = 1e-4 * u(rng);
      }
      state.void_ratio = 0.7;
      state.plastic_shear_strain = 0.01;
      const double w = size * u(rng);
      Mat3 spin = Mat3::Zero();
      spin(1, 0) = w;
      spin(0, 1) = -w;
      MaterialState general = state, in_plane = state;
      rotate_state(general, spin);
      rotate_state_about_z(in_plane, w);
      EXPECT_LE((general.stress - in_plane.stress).norm(), 1e-15 * 1e5 * 6) << w;
      EXPECT_LE((general.intergranular_strain - in_plane.intergranular_strain).norm(),
                1e-15 * 1e-4 * 6)
          << w;
      EXPECT_EQ(in_plane.void_ratio, state.void_ratio);
      EXPECT_EQ(in_plane.plastic_shear_strain, state.plastic_shear_strain);
    }
  }
}

}  // namespace
}  // namespace pilempm::mpm
