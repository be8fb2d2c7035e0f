#pragma once
// Bolton's (1986) stress-dilatancy relations for triaxial compression, with the dilatancy angle
// after Schanz & Vermeer (1996). docs/study.md §3.

namespace pilempm {

/// Peak friction and dilatancy of a sand by Bolton (1986), triaxial compression.
struct BoltonResult {
  double relative_dilatancy_index = 0.0;  ///< I_R = I_D (10 - ln p') - 1 [-], not clipped
  double phi_max_deg = 0.0;               ///< phi_max = phi_c + 3 I_R [deg]
  double dilatancy_rate = 0.0;            ///< (-d eps_v / d eps_1)_max = 0.3 I_R [-]
  double sin_psi_max = 0.0;               ///< sin psi_max = 0.3 I_R / (2 + 0.3 I_R) [-]
  double psi_max_deg = 0.0;               ///< psi_max [deg]; negative means contraction
};

/// Bolton (1986) at relative density `relative_density` (I_D in [0, 1]), critical-state friction
/// angle `phi_c_deg` in (0, 90) degrees and mean effective stress `mean_stress` [Pa] (> 0).
/// I_R is kept as it is, also where it is negative (very high pressure) or above Bolton's cap of
/// 4 (very low pressure), as the study's table does. Throws InvalidValue (keys "I_D",
/// "phi_c_deg", "p_Pa") for an input outside its range, and for a pressure at which the result
/// leaves 0 < phi_max < 90 deg or |sin psi_max| <= 1.
BoltonResult bolton(double relative_density, double phi_c_deg, double mean_stress);

}  // namespace pilempm
