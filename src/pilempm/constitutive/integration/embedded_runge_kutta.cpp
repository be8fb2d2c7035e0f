#include "pilempm/constitutive/integration/embedded_runge_kutta.hpp"

#include "pilempm/core/error.hpp"

namespace pilempm {

void IntegratorSettings::validate() const {
  if (!(tolerance > 0.0 && tolerance <= 0.1))
    throw InvalidValue("tolerance", format_value(tolerance), "in (0, 0.1]");
  if (fixed_substeps < 0)
    throw InvalidValue("fixed_substeps", std::to_string(fixed_substeps), ">= 0 (0: adaptive)");
  if (max_substeps < 1) throw InvalidValue("max_substeps", std::to_string(max_substeps), ">= 1");
  if (!(min_substep > 0.0 && min_substep < 1.0))
    throw InvalidValue("min_substep", format_value(min_substep), "in (0, 1)");
  if (!(min_mean_stress > 0.0 && std::isfinite(min_mean_stress)))
    throw InvalidValue("min_mean_stress_Pa", format_value(min_mean_stress), "> 0");
}

IntegratorSettings::Scheme parse_integrator_scheme(std::string_view text, std::string_view key) {
  if (text == "heun-euler") return IntegratorSettings::Scheme::heun_euler;
  if (text == "bogacki-shampine") return IntegratorSettings::Scheme::bogacki_shampine;
  throw InvalidValue(std::string(key), std::string(text), "\"heun-euler\" or \"bogacki-shampine\"");
}

std::string_view to_string(IntegratorSettings::Scheme scheme) {
  return scheme == IntegratorSettings::Scheme::heun_euler ? "heun-euler" : "bogacki-shampine";
}

}  // namespace pilempm
