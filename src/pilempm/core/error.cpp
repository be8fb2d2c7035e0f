#include "pilempm/core/error.hpp"

#include <fmt/format.h>

namespace pilempm {

std::string message_text(std::string_view text, std::size_t max_characters) {
  std::string out;
  std::size_t characters = 0;
  std::size_t i = 0;
  while (i < text.size()) {
    if (characters == max_characters) return out + "...";
    const auto byte = static_cast<unsigned char>(text[i]);
    // The length of the UTF-8 sequence this byte starts (0: not a lead byte).
    const std::size_t length = byte < 0x80                           ? 1
                               : (byte >> 5) == 0x6 && byte >= 0xC2  ? 2
                               : (byte >> 4) == 0xE                  ? 3
                               : (byte >> 3) == 0x1E && byte <= 0xF4 ? 4
                                                                     : 0;
    bool valid = length > 0 && i + length <= text.size();
    for (std::size_t k = 1; valid && k < length; ++k)
      valid = (static_cast<unsigned char>(text[i + k]) & 0xC0) == 0x80;
    if (!valid) {
      out += fmt::format("\\x{:02X}", byte);
      ++i;
    } else if (byte < 0x20 || byte == 0x7F) {
      out += fmt::format("\\x{:02X}", byte);
      ++i;
    } else if (byte == 0xC2 && static_cast<unsigned char>(text[i + 1]) < 0xA0) {  // C1 controls
      out += fmt::format("\\u{:04X}", static_cast<unsigned char>(text[i + 1]));
      i += 2;
    } else {
      out.append(text.substr(i, length));
      i += length;
    }
    ++characters;
  }
  return out;
}

InvalidValue::InvalidValue(std::string key, std::string value, std::string allowed)
    : Error(fmt::format("{} = {} is not allowed: must be {}", message_text(key, 200),
                        message_text(value), allowed)),
      key_(std::move(key)),
      value_(std::move(value)),
      allowed_(std::move(allowed)) {}

namespace {
std::string input_message(const std::string& file, long line, const std::string& key,
                          const std::string& value, const std::string& reason) {
  // The file, key and value come from the user: escaped and cut (an ESC sequence in a value
  // must not recolour the terminal, and a megabyte value does not belong in one line).
  std::string where = file.empty() ? std::string("<input>") : message_text(file, 400);
  if (line > 0) where += fmt::format(":{}", line);
  if (key.empty()) return fmt::format("{}: {}", where, reason);
  if (value.empty()) return fmt::format("{}: {}: {}", where, message_text(key, 200), reason);
  return fmt::format("{}: {} = {}: {}", where, message_text(key, 200), message_text(value), reason);
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
