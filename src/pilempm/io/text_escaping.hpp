#pragma once
// Escaping of text for the JSON and CSV files the program writes.
#include <string>
#include <string_view>

namespace pilempm {

/// A JSON string literal: the text in double quotes with ", \ and control characters escaped.
std::string json_quote(std::string_view text);

/// A CSV field: the text as it is, or in double quotes (with " doubled) when it holds a comma,
/// a quote or a line break (RFC 4180).
std::string csv_field(std::string_view text);

}  // namespace pilempm
