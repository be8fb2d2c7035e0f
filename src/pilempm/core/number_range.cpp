#include "pilempm/core/number_range.hpp"

#include <fmt/format.h>

#include <cmath>

#include "pilempm/core/error.hpp"

namespace pilempm {

bool NumberRange::contains(double value) const {
  if (!std::isfinite(value)) return false;
  if (lower_open ? !(value > lower) : !(value >= lower)) return false;
  if (upper_open ? !(value < upper) : !(value <= upper)) return false;
  return true;
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
