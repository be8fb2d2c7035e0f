#pragma once
// Parts of centrifuge case files shared by the tests of the reader (io) and of the run (study).

namespace pilempm::test_support {

// The Mohr-Coulomb sand of examples/centrifuge/mpm2_mohr_coulomb.toml as a [[material]] named
// "mc-sand": φ and ψ from Bolton at the tip's stress level, E50 of the original set's triaxial
// test at σ3 = 1 MPa, ν from K0, c = 1 kPa (docs/centrifuge.md, "Mohr-Coulomb sand for MPM-2").
inline constexpr const char* kMohrCoulombSandMaterial = R"([[material]]
name = "mc-sand"
model = "mohr-coulomb"
young_modulus_MPa = 150.0
poisson_ratio = 0.31
cohesion_kPa = 1.0
friction_angle_deg = 33.0
dilatancy_angle_deg = 5.0
)";

}  // namespace pilempm::test_support
