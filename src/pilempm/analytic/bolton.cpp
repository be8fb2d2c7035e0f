#include "pilempm/analytic/bolton.hpp"

#include <cmath>

#include "pilempm/core/error.hpp"
#include "pilempm/core/tensor.hpp"

namespace pilempm {

namespace {
void require(bool condition, const char* key, double value, const char* allowed) {
  if (!condition) throw InvalidValue(key, format_value(value), allowed);
}
}  // namespace

BoltonResult bolton(double relative_density, double phi_c_deg, double mean_stress) {
  require(relative_density >= 0.0 && relative_density <= 1.0, "I_D", relative_density, "in [0, 1]");
  require(phi_c_deg > 0.0 && phi_c_deg < 90.0, "phi_c_deg", phi_c_deg, "in (0, 90) degrees");
  require(mean_stress > 0.0 && std::isfinite(mean_stress), "p_Pa", mean_stress, "> 0");

  BoltonResult result;
  const double p_kPa = mean_stress / 1.0e3;  // Bolton's ln p' takes p' in kPa
  // Bolton (1986), triaxial: I_R = I_D (10 - ln p') - 1, phi_max = phi_c + 3 I_R.
  result.relative_dilatancy_index = relative_density * (10.0 - std::log(p_kPa)) - 1.0;
  result.phi_max_deg = phi_c_deg + 3.0 * result.relative_dilatancy_index;
  // Bolton (1986): (-d eps_v / d eps_1)_max = 0.3 I_R.
  result.dilatancy_rate = 0.3 * result.relative_dilatancy_index;
  // Schanz & Vermeer (1996): sin psi = (-d eps_v/d eps_1) / (2 - d eps_v/d eps_1).
  result.sin_psi_max = result.dilatancy_rate / (2.0 + result.dilatancy_rate);
  require(result.phi_max_deg > 0.0 && result.phi_max_deg < 90.0 && result.dilatancy_rate > -1.0 &&
              std::abs(result.sin_psi_max) <= 1.0,
          "p_Pa", mean_stress,
          "in the range where Bolton's relation gives 0 < phi_max < 90 deg and |sin psi_max| <= 1");
  result.psi_max_deg = std::asin(result.sin_psi_max) * 180.0 / kPi;
  return result;
}

}  // namespace pilempm
