#include "pilempm/io/output/format.hpp"

#include <fmt/format.h>

#include <cmath>

namespace pilempm {

namespace {

// Finite values only. + 0.0: a negated zero is written "0", not "-0".
std::string finite_number(double value, int significant_digits) {
  return significant_digits > 0 ? fmt::format("{:.{}g}", value + 0.0, significant_digits)
                                : fmt::format("{}", value + 0.0);
}

}  // namespace

std::string csv_number(double value, int significant_digits) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0.0 ? "inf" : "-inf";
  return finite_number(value, significant_digits);
}

std::string json_number(double value, int significant_digits) {
  return std::isfinite(value) ? finite_number(value, significant_digits) : "null";
}

std::string fixed_number(double value, int decimals) {
  if (!std::isfinite(value)) return "-";
  return fmt::format("{:.{}f}", value + 0.0, decimals);
}

std::string shown_number(double value, std::string_view format) {
  if (!std::isfinite(value)) return "-";
  return fmt::format(fmt::runtime(format), value + 0.0);
}

std::string csv_field(std::string_view text) {
  if (text.find_first_of(",\"\n\r") == std::string_view::npos) return std::string(text);
  std::string out = "\"";
  for (char ch : text) {
    if (ch == '"') out += '"';
    out += ch;
  }
  return out + "\"";
}

std::string csv_row(const std::vector<std::string>& cells) {
  std::string out;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (i > 0) out += ',';
    out += csv_field(cells[i]);
  }
  return out + '\n';
}

CsvText::CsvText(std::string_view comment, const std::vector<std::string>& header) {
  if (!comment.empty()) text_ = "# " + std::string(comment) + "\n";
  add(header);
}

std::string markdown_cell(std::string_view text) {
  std::string out;
  for (char ch : text) {
    if (ch == '|') out += '\\';
    out += ch == '\n' ? ' ' : ch;
  }
  return out;
}

std::string markdown_table(const std::vector<std::string>& header,
                           const std::vector<std::vector<std::string>>& rows, std::size_t left) {
  std::string out = "|";
  for (const auto& h : header) out.append(" ").append(markdown_cell(h)).append(" |");
  out += "\n|";
  for (std::size_t i = 0; i < header.size(); ++i) out += i < left ? " --- |" : " ---: |";
  out += '\n';
  for (const auto& row : rows) {
    out += '|';
    for (const auto& cell : row) out.append(" ").append(markdown_cell(cell)).append(" |");
    out += '\n';
  }
  return out;
}

}  // namespace pilempm
