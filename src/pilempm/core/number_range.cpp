#include "pilempm/core/number_range.hpp"

#include <fmt/format.h>

#include <cmath>

#include "pilempm/core/error.hpp"

namespace pilempm {

bool NumberRange::contains(double value) const {
  return problem(value).empty();
}

std::string NumberRange::problem(double value) const {
  const bool inside = std::isfinite(value) && (lower_open ? value > lower : value >= lower) &&
                      (upper_open ? value < upper : value <= upper);
  if (!inside) return fmt::format("out of range: must be {}", describe());
  const double magnitude = std::fabs(value);
  if (magnitude > kMaxMagnitude || (magnitude > 0.0 && magnitude < 1.0 / kMaxMagnitude))
    return fmt::format(
        "out of range: must be 0 or of a magnitude in [1e-100, 1e+100] (it is multiplied by "
        "units and other values){}",
        std::isfinite(lower) || std::isfinite(upper) ? ", and " + describe() : std::string());
  return {};
}

std::string NumberRange::describe() const {
  const bool has_lower = std::isfinite(lower), has_upper = std::isfinite(upper);
  if (has_lower && has_upper)
    return fmt::format("in {}{}, {}{}", lower_open ? "(" : "[", format_value(lower),
                       format_value(upper), upper_open ? ")" : "]");
  if (has_lower) return fmt::format("{} {}", lower_open ? ">" : ">=", format_value(lower));
  if (has_upper) return fmt::format("{} {}", upper_open ? "<" : "<=", format_value(upper));
  return "a finite number";
}

}  // namespace pilempm
