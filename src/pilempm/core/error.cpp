#include "pilempm/core/error.hpp"

#include <fmt/format.h>

namespace pilempm {

InvalidValue::InvalidValue(std::string key, std::string value, std::string allowed)
    : Error(fmt::format("{} = {} is not allowed: must be {}", key, value, allowed)),
      key_(std::move(key)),
      value_(std::move(value)),
      allowed_(std::move(allowed)) {}

namespace {
std::string input_message(const std::string& file, long line, const std::string& key,
                          const std::string& value, const std::string& reason) {
  std::string where = file.empty() ? std::string("<input>") : file;
  if (line > 0) where += fmt::format(":{}", line);
  if (key.empty()) return fmt::format("{}: {}", where, reason);
  if (value.empty()) return fmt::format("{}: {}: {}", where, key, reason);
  return fmt::format("{}: {} = {}: {}", where, key, value, reason);
}
}  // namespace

InputError::InputError(std::string file, long line, std::string key, std::string value,
                       std::string reason)
    : Error(input_message(file, line, key, value, reason)),
      file_(std::move(file)),
      line_(line),
      key_(std::move(key)) {}

std::string format_value(double value) {
  return fmt::format("{}", value);
}

}  // namespace pilempm
