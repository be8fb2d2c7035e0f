#pragma once
// Errors that carry what a user needs to fix the input: which key, which value, what is allowed,
// and (once the input layer has added it) which file and line.
#include <stdexcept>
#include <string>
#include <string_view>

namespace pilempm {

/// Base class of every error pilempm throws on purpose.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A value outside its allowed range, raised where the value is checked (for example when a
/// parameter set is validated). The input layer catches it and rethrows an InputError with the
/// file and line of the offending key.
class InvalidValue : public Error {
 public:
  InvalidValue(std::string key, std::string value, std::string allowed);
  const std::string& key() const { return key_; }
  const std::string& value() const { return value_; }
  const std::string& allowed() const { return allowed_; }

 private:
  std::string key_, value_, allowed_;
};

/// Bad input in a file or on the command line: "file:line: key = value: reason".
class InputError : public Error {
 public:
  InputError(std::string file, long line, std::string key, std::string value, std::string reason);
  const std::string& file() const { return file_; }
  long line() const { return line_; }
  const std::string& key() const { return key_; }

 private:
  std::string file_;
  long line_;
  std::string key_;
};

/// Text from the user made safe for one line of a message: control characters (C0, DEL, C1) and
/// bytes that are not UTF-8 escaped as \xNN or \u00NN, and text longer than `max_characters`
/// characters cut on a character boundary with "..." appended.
std::string message_text(std::string_view text, std::size_t max_characters = 80);

/// Formats a double with enough digits to round-trip, without trailing noise for short values.
std::string format_value(double value);

}  // namespace pilempm
