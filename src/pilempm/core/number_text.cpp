#include "pilempm/core/number_text.hpp"

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

}  // namespace pilempm
