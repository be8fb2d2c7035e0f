#pragma once
// What a model's parameter reader sees of one [[material]] table: typed, range-checked keys and
// errors that name where the value was written. The model registry depends on this small
// interface only; io/ implements it on its TOML reader (io/material_reader.cpp), so a model's
// folder reads its own keys without knowing the file format, and a test can feed it any source.
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pilempm/core/error.hpp"
#include "pilempm/core/number_range.hpp"

namespace pilempm {

class ParameterSource {
 public:
  virtual ~ParameterSource() = default;

  /// Whether the key is present (counts as asking for it).
  virtual bool contains(std::string_view key) = 0;
  /// Whether the key holds a string (false when absent).
  virtual bool holds_string(std::string_view key) = 0;

  /// A required number in the range; an absent key or a value outside it is an InputError.
  virtual double number(std::string_view key, const NumberRange& range) = 0;
  virtual std::optional<double> optional_number(std::string_view key, const NumberRange& range) = 0;
  virtual double number_or(std::string_view key, double fallback, const NumberRange& range) = 0;
  virtual bool boolean_or(std::string_view key, bool fallback) = 0;
  /// A string out of a fixed list (the message lists them).
  virtual std::string choice(std::string_view key, const std::vector<std::string>& allowed) = 0;
  virtual std::optional<std::string> optional_choice(std::string_view key,
                                                     const std::vector<std::string>& allowed) = 0;
  /// A sub-table (nullptr when absent; an InputError when the key holds something else).
  virtual std::unique_ptr<ParameterSource> table(std::string_view key) = 0;

  /// The keys this table may hold, declared before reading (completes "allowed keys" lists).
  virtual void declare(const std::vector<std::string>& keys) = 0;
  /// Throws an InputError for a key that nobody asked about.
  virtual void check_no_unknown_keys() const = 0;

  /// An InputError at the key, naming the file, line and key.
  virtual InputError error(std::string_view key, const std::string& reason) const = 0;
  /// An InvalidValue of library validation as an InputError at the input's key (`keys` maps the
  /// library's SI key names to the input's); `origin` says where a value not in the table came
  /// from.
  virtual InputError error_from(const InvalidValue& invalid, const KeyMap& keys = {},
                                const std::string& origin = "") const = 0;
};

}  // namespace pilempm
