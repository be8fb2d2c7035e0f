#include "pilempm/io/toml_reader.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

namespace pilempm {

namespace {

long line_of_node(const toml::node& node) {
  return static_cast<long>(node.source().begin.line);
}

// Edit distance with adjacent transpositions (optimal string alignment), ignoring case, for
// "did you mean": "stpes" is one edit from "steps".
std::size_t edit_distance(std::string_view a, std::string_view b) {
  const auto lower = [](char c) {
    return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  };
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) &&
          lower(a[i - 2]) == lower(b[j - 1]))
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[n][m];
}

std::string quoted_list(const std::vector<std::string>& items) {
  std::vector<std::string> q;
  q.reserve(items.size());
  for (const auto& s : items) q.push_back(fmt::format("\"{}\"", s));
  return fmt::format("{}", fmt::join(q, ", "));
}

InputError parse_error_to_input_error(const toml::parse_error& e, const std::string& file) {
  return InputError(file, static_cast<long>(e.source().begin.line), "", "",
                    fmt::format("TOML syntax error: {}", e.description()));
}

}  // namespace

std::string read_case_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), 0, "", "", "cannot open the file for reading");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

toml::table parse_toml_file(const std::filesystem::path& path) {
  return parse_toml_text(read_case_text(path), path.string());
}

toml::table parse_toml_text(std::string_view text, const std::string& source_name) {
  try {
    return toml::parse(text, source_name);
  } catch (const toml::parse_error& e) {
    throw parse_error_to_input_error(e, source_name);
  }
}

std::string toml_text(const toml::node& node) {
  // Written here rather than by toml++'s printer, which quotes strings with ' and prints
  // floats with all 17 digits (0.80000000000000004): messages show what the user wrote.
  if (const auto* s = node.as_string()) {
    std::string out = "\"";
    for (char ch : s->get()) {
      if (ch == '"' || ch == '\\') out += '\\';
      out += ch == '\n' ? ' ' : ch;
    }
    return out + "\"";
  }
  if (const auto* i = node.as_integer()) return std::to_string(i->get());
  if (const auto* f = node.as_floating_point()) return format_value(f->get());
  if (const auto* b = node.as_boolean()) return b->get() ? "true" : "false";
  if (const auto* array = node.as_array()) {
    std::string out = "[";
    for (std::size_t i = 0; i < array->size(); ++i) {
      if (i > 0) out += ", ";
      out += toml_text(*array->get(i));
    }
    return out + "]";
  }
  if (const auto* table = node.as_table()) {
    std::string out = "{";
    bool first = true;
    for (auto&& [key, value] : *table) {
      out += first ? " " : ", ";
      first = false;
      out += fmt::format("{} = {}", key.str(), toml_text(value));
    }
    return out + (first ? "}" : " }");
  }
  std::ostringstream os;  // dates and times
  node.visit([&os](const auto& n) { os << n; });
  return os.str();
}

std::string toml_type_name(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a floating-point number";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::date:
      return "a date";
    case toml::node_type::time:
      return "a time";
    case toml::node_type::date_time:
      return "a date-time";
    default:
      return "nothing";
  }
}

TableReader::TableReader(const toml::table& table, std::string file, std::string path)
    : table_(&table), file_(std::move(file)), path_(std::move(path)) {}

long TableReader::line() const {
  const long own = line_of_node(*table_);
  if (own > 0) return own;
  long first = 0;
  for (auto&& [key, value] : *table_) {
    const long l = line_of_node(value);
    if (l > 0 && (first == 0 || l < first)) first = l;
  }
  return first;
}

const toml::node* TableReader::find(std::string_view key) const {
  return table_->get(key);
}

void TableReader::declare(const std::vector<std::string>& keys) {
  asked_.insert(keys.begin(), keys.end());
}

bool TableReader::contains(std::string_view key) {
  asked_.emplace(key);
  return find(key) != nullptr;
}

const toml::node* TableReader::node(std::string_view key) {
  asked_.emplace(key);
  return find(key);
}

long TableReader::line_of(std::string_view key) const {
  if (const toml::node* n = find(key)) {
    const long l = line_of_node(*n);
    if (l > 0) return l;
  }
  return line();
}

std::string TableReader::full_key(std::string_view key) const {
  if (path_.empty()) return std::string(key);
  return fmt::format("{}.{}", path_, key);
}

std::string TableReader::value_text(std::string_view key) const {
  const toml::node* n = find(key);
  return n ? toml_text(*n) : std::string();
}

InputError TableReader::error(std::string_view key, const std::string& reason) const {
  return InputError(file_, line_of(key), full_key(key), value_text(key), reason);
}

InputError TableReader::missing(std::string_view key, const std::string& what) const {
  for (auto&& [present, value] : *table_) {
    // Close enough to be a misspelling: about one edit per four characters.
    const std::size_t allowed_edits = std::max<std::size_t>(1, key.size() / 4);
    if (asked_.count(present.str()) != 0 || edit_distance(present.str(), key) > allowed_edits)
      continue;
    const long l = line_of_node(value);
    return InputError(
        file_, l > 0 ? l : line(), full_key(present.str()), toml_text(value),
        fmt::format("unknown key (did you mean \"{}\"? {} is missing)", key, full_key(key)));
  }
  return error(key, "missing: " + what);
}

InputError TableReader::table_error(const std::string& reason) const {
  return InputError(file_, line(), path_.empty() ? std::string("(top level)") : path_, "", reason);
}

InputError TableReader::error_from(const InvalidValue& invalid, const KeyMap& keys,
                                   const std::string& origin) const {
  std::string key = invalid.key();
  if (auto it = keys.find(key); it != keys.end()) key = it->second;
  const std::string reason = fmt::format("not allowed: must be {}", invalid.allowed());
  if (find(key) != nullptr) return error(key, reason);
  // The value did not come from this table: point at the table and say where it came from.
  return InputError(file_, line(), full_key(key), invalid.value(),
                    origin.empty() ? reason : fmt::format("{} ({})", reason, origin));
}

void TableReader::wrong_type(std::string_view key, const toml::node& node,
                             const char* expected) const {
  throw error(key, fmt::format("wrong type: expected {}, got {}", expected, toml_type_name(node)));
}

double TableReader::to_number(std::string_view key, const toml::node& node,
                              const NumberRange& range, const std::string& label, long line) const {
  double value = 0.0;
  if (const auto* i = node.as_integer()) {
    value = static_cast<double>(i->get());
  } else if (const auto* f = node.as_floating_point()) {
    value = f->get();
  } else {
    throw InputError(file_, line, label, toml_text(node),
                     fmt::format("wrong type: expected a number, got {}", toml_type_name(node)));
  }
  if (!range.contains(value))
    throw InputError(file_, line, label, toml_text(node),
                     fmt::format("out of range: must be {}", range.describe()));
  (void)key;
  return value;
}

std::optional<double> TableReader::optional_number(std::string_view key, const NumberRange& range) {
  const toml::node* n = node(key);
  if (n == nullptr) return std::nullopt;
  return to_number(key, *n, range, full_key(key), line_of(key));
}

double TableReader::number(std::string_view key, const NumberRange& range) {
  if (auto v = optional_number(key, range)) return *v;
  throw missing(key, fmt::format("a number {} is required", range.describe()));
}

double TableReader::number_or(std::string_view key, double fallback, const NumberRange& range) {
  return optional_number(key, range).value_or(fallback);
}

std::optional<int> TableReader::optional_integer(std::string_view key, int min, int max) {
  const toml::node* n = node(key);
  if (n == nullptr) return std::nullopt;
  const auto* i = n->as_integer();
  if (i == nullptr) wrong_type(key, *n, "an integer");
  const std::int64_t v = i->get();
  if (v < min || v > max)
    throw error(key, fmt::format("out of range: must be an integer in [{}, {}]", min, max));
  return static_cast<int>(v);
}

int TableReader::integer(std::string_view key, int min, int max) {
  if (auto v = optional_integer(key, min, max)) return *v;
  throw missing(key, fmt::format("an integer in [{}, {}] is required", min, max));
}

int TableReader::integer_or(std::string_view key, int fallback, int min, int max) {
  return optional_integer(key, min, max).value_or(fallback);
}

bool TableReader::boolean_or(std::string_view key, bool fallback) {
  const toml::node* n = node(key);
  if (n == nullptr) return fallback;
  const auto* b = n->as_boolean();
  if (b == nullptr) wrong_type(key, *n, "true or false");
  return b->get();
}

std::optional<std::string> TableReader::optional_string(std::string_view key) {
  const toml::node* n = node(key);
  if (n == nullptr) return std::nullopt;
  const auto* s = n->as_string();
  if (s == nullptr) wrong_type(key, *n, "a string");
  return s->get();
}

std::string TableReader::string(std::string_view key) {
  if (auto v = optional_string(key)) return *v;
  throw missing(key, "a string is required");
}

std::optional<std::string> TableReader::optional_choice(std::string_view key,
                                                        const std::vector<std::string>& allowed) {
  auto v = optional_string(key);
  if (!v) return v;
  if (std::find(allowed.begin(), allowed.end(), *v) == allowed.end())
    throw error(key, fmt::format("not allowed: must be one of {}", quoted_list(allowed)));
  return v;
}

std::string TableReader::choice(std::string_view key, const std::vector<std::string>& allowed) {
  if (auto v = optional_choice(key, allowed)) return *v;
  throw missing(key, fmt::format("one of {} is required", quoted_list(allowed)));
}

std::vector<double> TableReader::number_array(std::string_view key, const NumberRange& range,
                                              std::size_t min_size, std::size_t max_size,
                                              bool scalar_ok) {
  const toml::node* n = node(key);
  const std::string size_text = min_size == max_size ? fmt::format("{}", min_size)
                                : max_size == std::numeric_limits<std::size_t>::max()
                                    ? fmt::format("at least {}", min_size)
                                    : fmt::format("{} to {}", min_size, max_size);
  if (n == nullptr)
    throw missing(
        key, fmt::format("an array of {} numbers {} is required", size_text, range.describe()));
  if (scalar_ok && (n->is_integer() || n->is_floating_point()))
    return {to_number(key, *n, range, full_key(key), line_of(key))};
  const auto* array = n->as_array();
  if (array == nullptr)
    wrong_type(key, *n, scalar_ok ? "a number or an array of numbers" : "an array of numbers");
  if (array->size() < min_size || array->size() > max_size)
    throw error(key,
                fmt::format("wrong size: {} entries given, {} allowed", array->size(), size_text));
  std::vector<double> values;
  values.reserve(array->size());
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& element = *array->get(i);
    long l = line_of_node(element);
    if (l <= 0) l = line_of(key);
    values.push_back(to_number(key, element, range, fmt::format("{}[{}]", full_key(key), i), l));
  }
  return values;
}

std::optional<TableReader> TableReader::table(std::string_view key) {
  const toml::node* n = node(key);
  if (n == nullptr) return std::nullopt;
  const auto* t = n->as_table();
  if (t == nullptr) wrong_type(key, *n, "a table");
  return TableReader(*t, file_, full_key(key));
}

std::vector<TableReader> TableReader::tables(std::string_view key) {
  const toml::node* n = node(key);
  std::vector<TableReader> result;
  if (n == nullptr) return result;
  const auto* array = n->as_array();
  if (array == nullptr) wrong_type(key, *n, "an array of tables");
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& element = *array->get(i);
    const auto* t = element.as_table();
    if (t == nullptr) {
      long l = line_of_node(element);
      if (l <= 0) l = line_of(key);
      throw InputError(
          file_, l, fmt::format("{}[{}]", full_key(key), i), toml_text(element),
          fmt::format("wrong type: expected a table, got {}", toml_type_name(element)));
    }
    result.emplace_back(*t, file_, fmt::format("{}[{}]", full_key(key), i));
  }
  return result;
}

void TableReader::check_no_unknown_keys() const {
  const toml::key* first = nullptr;
  const toml::node* first_node = nullptr;
  long first_line = 0;
  for (auto&& [key, value] : *table_) {
    if (asked_.count(key.str()) != 0) continue;
    const long l = line_of_node(value);
    if (first == nullptr || (l > 0 && l < first_line)) {
      first = &key;
      first_node = &value;
      first_line = l;
    }
  }
  if (first == nullptr) return;
  const std::string name(first->str());
  std::vector<std::string> allowed(asked_.begin(), asked_.end());
  std::string guess;
  // Suggest only close matches: about one edit per four characters.
  std::size_t best = std::max<std::size_t>(1, name.size() / 4) + 1;
  for (const auto& a : allowed) {
    const std::size_t d = edit_distance(name, a);
    if (d < best) {
      best = d;
      guess = a;
    }
  }
  std::string reason = "unknown key";
  if (!guess.empty()) reason += fmt::format(" (did you mean \"{}\"?)", guess);
  reason += allowed.empty() ? std::string("; no keys are allowed here")
                            : fmt::format("; allowed here: {}", fmt::join(allowed, ", "));
  std::string value = toml_text(*first_node);
  if (value.size() > 60) value = value.substr(0, 57) + "...";
  throw InputError(file_, first_line > 0 ? first_line : line(), full_key(name), value, reason);
}

}  // namespace pilempm
