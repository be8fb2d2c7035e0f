#pragma once
// Strict reading of TOML input. A TableReader wraps one table of a parsed document, reads typed
// keys with range checks and remembers every key it was asked about, so that a key nobody asked
// about can be reported as unknown (a misspelt key is an error, never silence). Every error is an
// InputError with the file, the line (from toml++'s source regions), the full dotted key
// (e.g. test[3].sigma3_kPa), the value as written and what is allowed.
#include <toml++/toml.h>

#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "pilempm/core/error.hpp"
#include "pilempm/core/number_range.hpp"

namespace pilempm {

/// The whole text of a case file; an unreadable file is an InputError naming it.
std::string read_case_text(const std::filesystem::path& path);
/// Parses a TOML file; a syntax error or an unreadable file becomes an InputError with the line.
toml::table parse_toml_file(const std::filesystem::path& path);
/// Parses TOML text; `source_name` is what messages call the file.
toml::table parse_toml_text(std::string_view text, const std::string& source_name);

class TableReader {
 public:
  /// `path` is the dotted key of this table in the document ("" for the root).
  TableReader(const toml::table& table, std::string file, std::string path);

  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }
  /// Line of the table's header (or of its first key), 0 when unknown.
  long line() const;

  /// Declares keys this table may hold before they are read, so that a misspelling of a key
  /// read later is not taken for it and the list of allowed keys is complete.
  void declare(const std::vector<std::string>& keys);
  /// Whether the key is present. Counts as asking for it.
  bool contains(std::string_view key);
  /// Line of the key's value (the table's line when the key is absent).
  long line_of(std::string_view key) const;
  /// "path.key" (or "key" at the root).
  std::string full_key(std::string_view key) const;
  /// The value as TOML text ("" when absent).
  std::string value_text(std::string_view key) const;
  /// The raw node (nullptr when absent). Counts as asking for it.
  const toml::node* node(std::string_view key);

  // Typed reads. `required` ones throw when the key is absent; `optional` ones return nothing;
  // `_or` ones return the fallback. Integers are accepted where a number is expected.
  double number(std::string_view key, const NumberRange& range);
  std::optional<double> optional_number(std::string_view key, const NumberRange& range);
  double number_or(std::string_view key, double fallback, const NumberRange& range);

  int integer(std::string_view key, int min, int max);
  std::optional<int> optional_integer(std::string_view key, int min, int max);
  int integer_or(std::string_view key, int fallback, int min, int max);

  bool boolean_or(std::string_view key, bool fallback);

  std::string string(std::string_view key);
  std::optional<std::string> optional_string(std::string_view key);
  /// A string out of a fixed list (the message lists them).
  std::string choice(std::string_view key, const std::vector<std::string>& allowed);
  std::optional<std::string> optional_choice(std::string_view key,
                                             const std::vector<std::string>& allowed);

  /// An array of numbers of a size in [min_size, max_size]; a single number counts as an array
  /// of one when `scalar_ok`.
  std::vector<double> number_array(std::string_view key, const NumberRange& range,
                                   std::size_t min_size, std::size_t max_size,
                                   bool scalar_ok = false);

  /// A sub-table (nullopt when absent; error when the key holds something else).
  std::optional<TableReader> table(std::string_view key);
  /// An array of tables ([[key]] or an array of inline tables); empty when absent.
  std::vector<TableReader> tables(std::string_view key);

  /// Throws an InputError for the first key (in source order) that no read asked about, with
  /// the keys that are allowed here and a guess at the intended one.
  void check_no_unknown_keys() const;

  /// An InputError at the key: "file:line: path.key = value: reason".
  InputError error(std::string_view key, const std::string& reason) const;
  /// The error for a required key that is absent: "missing: <what>", or, when the table holds
  /// an unknown key that looks like a misspelling of it, "unknown key (did you mean ...)" at
  /// that key's line.
  InputError missing(std::string_view key, const std::string& what) const;
  /// An InputError at the table's own line, naming the table.
  InputError table_error(const std::string& reason) const;
  /// Converts an InvalidValue from library validation into an InputError at the offending key
  /// of this table. `keys` maps library keys to input keys; when the key is absent from the
  /// table (the value came from elsewhere, e.g. a base set), the error points at the table and
  /// says `origin`.
  InputError error_from(const InvalidValue& invalid, const KeyMap& keys = {},
                        const std::string& origin = "") const;

 private:
  const toml::node* find(std::string_view key) const;
  [[noreturn]] void wrong_type(std::string_view key, const toml::node& node,
                               const char* expected) const;
  double to_number(std::string_view key, const toml::node& node, const NumberRange& range,
                   const std::string& label, long line) const;

  const toml::table* table_;
  std::string file_;
  std::string path_;
  std::set<std::string, std::less<>> asked_;
};

/// TOML text of a node, as it would be written in a file (strings quoted).
std::string toml_text(const toml::node& node);
/// Friendly name of a node's type ("a string", "an integer", ...).
std::string toml_type_name(const toml::node& node);

}  // namespace pilempm
