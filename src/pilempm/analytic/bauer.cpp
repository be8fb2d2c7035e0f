#include "pilempm/analytic/bauer.hpp"

#include <fmt/format.h>
#include <cmath>

#include "pilempm/core/error.hpp"

namespace pilempm {

namespace {

void require(bool condition, const char* key, double value, const std::string& allowed) {
  if (!condition) throw InvalidValue(key, format_value(value), allowed);
}

void require_hardness_and_exponent(double h_s, double n) {
  require(h_s > 0.0 && std::isfinite(h_s), "h_s_Pa", h_s, "> 0");
  require(n > 0.0 && n < 1.0, "n", n, "in (0, 1)");
}

void require_mean_stress(double mean_stress) {
  require(mean_stress >= 0.0 && std::isfinite(mean_stress), "p_Pa", mean_stress, ">= 0");
}

}  // namespace

double bauer_void_ratio(double e_p0, double h_s, double n, double mean_stress) {
  require(e_p0 > 0.0 && std::isfinite(e_p0), "e_p0", e_p0, "> 0");
  require_hardness_and_exponent(h_s, n);
  require_mean_stress(mean_stress);
  // Bauer (1996): e_p = e_p0 exp[-(3 p / h_s)^n].
  return e_p0 * std::exp(-std::pow(3.0 * mean_stress / h_s, n));
}

std::vector<BauerRow> bauer_table(const HypoplasticParameters& parameters,
                                  std::span<const double> mean_stresses) {
  require_hardness_and_exponent(parameters.h_s, parameters.n);
  require(parameters.e_d0 > 0.0 && std::isfinite(parameters.e_d0), "e_d0", parameters.e_d0, "> 0");
  require(parameters.e_c0 > parameters.e_d0 && std::isfinite(parameters.e_c0), "e_c0",
          parameters.e_c0, fmt::format("> e_d0 = {} (e_d0 < e_c0 < e_i0)", parameters.e_d0));
  require(parameters.e_i0 > parameters.e_c0 && std::isfinite(parameters.e_i0), "e_i0",
          parameters.e_i0, fmt::format("> e_c0 = {} (e_d0 < e_c0 < e_i0)", parameters.e_c0));

  std::vector<BauerRow> rows;
  rows.reserve(mean_stresses.size());
  for (const double mean_stress : mean_stresses) {
    require_mean_stress(mean_stress);
    rows.push_back({mean_stress, limit_void_ratios(parameters, mean_stress)});
  }
  return rows;
}

}  // namespace pilempm
