#include "pilempm/io/output/json_writer.hpp"

#include <fmt/format.h>

#include "pilempm/io/output/format.hpp"

namespace pilempm {

namespace {

constexpr int kDigits = 10;

}  // namespace

std::string json_quote(std::string_view text) {
  std::string out = "\"";
  for (char ch : text) {
    switch (ch) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\r':
        out += "\\r";
        break;
      default:
        if (static_cast<unsigned char>(ch) < 0x20)
          out += fmt::format("\\u{:04x}", static_cast<unsigned>(static_cast<unsigned char>(ch)));
        else
          out += ch;
    }
  }
  return out + "\"";
}

JsonWriter::JsonWriter() {
  open("", '{');
}

JsonWriter& JsonWriter::object(std::string_view key) {
  return open(key, '{');
}

JsonWriter& JsonWriter::end() {
  const char close = closers_.back();
  closers_.pop_back();
  first_.pop_back();
  out_ += fmt::format("\n{:{}}{}", "", 2 * closers_.size(), close);
  return *this;
}

JsonWriter& JsonWriter::number(std::string_view key, double value) {
  return raw(key, json_number(value, kDigits));
}

JsonWriter& JsonWriter::integer(std::string_view key, long value) {
  return raw(key, std::to_string(value));
}

JsonWriter& JsonWriter::boolean(std::string_view key, bool value) {
  return raw(key, value ? "true" : "false");
}

JsonWriter& JsonWriter::string(std::string_view key, std::string_view value) {
  return raw(key, json_quote(value));
}

JsonWriter& JsonWriter::numbers(std::string_view key, const std::vector<double>& values) {
  std::string list = "[";
  for (std::size_t i = 0; i < values.size(); ++i)
    list.append(i ? ", " : "").append(json_number(values[i], kDigits));
  return raw(key, list + "]");
}

std::string JsonWriter::finish() {
  while (!closers_.empty()) end();
  return out_ + "\n";
}

JsonWriter& JsonWriter::open(std::string_view key, char opener) {
  if (!closers_.empty()) prefix(key);
  out_ += opener;
  closers_.push_back(opener == '{' ? '}' : ']');
  first_.push_back(true);
  return *this;
}

void JsonWriter::prefix(std::string_view key) {
  out_ += first_.back() ? "\n" : ",\n";
  first_.back() = false;
  out_ += fmt::format("{:{}}", "", 2 * closers_.size());
  if (!key.empty()) out_ += json_quote(key) + ": ";
}

JsonWriter& JsonWriter::raw(std::string_view key, const std::string& text) {
  prefix(key);
  out_ += text;
  return *this;
}

}  // namespace pilempm
