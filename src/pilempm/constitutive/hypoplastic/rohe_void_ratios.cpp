#include "pilempm/constitutive/hypoplastic/rohe_void_ratios.hpp"

#include <cmath>

#include "pilempm/core/error.hpp"

namespace pilempm {

RoheReferenceVoidRatios rohe_reference_void_ratios(double vertical_stress) {
  if (!(vertical_stress >= 0.0 && std::isfinite(vertical_stress)))
    throw InvalidValue("sigma_v_Pa", format_value(vertical_stress), ">= 0");
  const double sigma_MPa = vertical_stress / 1.0e6;
  // Rohe (2010): common argument 0.0003 sigma_v'^2 + 0.0256 sigma_v' + 2.1669 (sigma_v' in MPa);
  // it has no real root, so it is positive for every stress.
  const double log_argument =
      std::log(0.0003 * sigma_MPa * sigma_MPa + 0.0256 * sigma_MPa + 2.1669);
  RoheReferenceVoidRatios result;
  result.e_c0 = 0.9501 - 0.0702 * log_argument;  // Rohe (2010)
  result.e_d0 = 0.6768 - 0.1698 * log_argument;  // Rohe (2010)
  result.e_i0 = 1.0926 - 0.0807 * log_argument;  // Rohe (2010)
  return result;
}

}  // namespace pilempm
