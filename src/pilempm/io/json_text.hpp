#pragma once
// JSON text helpers shared by every JSON the program writes.
#include <string>
#include <string_view>

namespace pilempm {

/// A JSON string literal: the text in double quotes with ", \ and control characters escaped.
std::string json_quote(std::string_view text);

}  // namespace pilempm
