#include "pilempm/core/number_text.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <string>

namespace pilempm {

std::optional<double> whole_number(std::string_view text) {
  if (text.empty()) return std::nullopt;
  const std::string copy(text);  // strtod needs the terminating zero
  char* end = nullptr;
  const double value = std::strtod(copy.c_str(), &end);
  if (end != copy.c_str() + copy.size()) return std::nullopt;
  return value;
}

double with_significant_digits(double value, int digits) {
  return std::strtod(fmt::format("{:.{}g}", value, digits).c_str(), nullptr);
}

}  // namespace pilempm
