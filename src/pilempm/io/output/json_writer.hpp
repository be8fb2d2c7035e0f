#pragma once
// JSON text: string literals, and a small writer of indented objects (numbers by json_number of
// format.hpp: null for NaN and infinities).
#include <string>
#include <string_view>
#include <vector>

namespace pilempm {

/// A JSON string literal: the text in double quotes with ", \ and control characters escaped.
std::string json_quote(std::string_view text);

/// An indented JSON object built key by key: `JsonWriter j; j.number("a", 1).object("b")...end();
/// j.finish()`. Numbers have 10 significant digits.
class JsonWriter {
 public:
  JsonWriter();
  JsonWriter& object(std::string_view key);
  JsonWriter& end();
  JsonWriter& number(std::string_view key, double value);
  JsonWriter& integer(std::string_view key, long value);
  JsonWriter& boolean(std::string_view key, bool value);
  JsonWriter& string(std::string_view key, std::string_view value);
  JsonWriter& numbers(std::string_view key, const std::vector<double>& values);
  /// Closes what is open and returns the text (ended by a line break).
  std::string finish();

 private:
  JsonWriter& open(std::string_view key, char opener);
  void prefix(std::string_view key);
  JsonWriter& raw(std::string_view key, const std::string& text);
  std::string out_;
  std::vector<char> closers_;
  std::vector<bool> first_;
};

}  // namespace pilempm
