#include "pilempm/study/csv_table.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "pilempm/core/error.hpp"
#include "pilempm/core/number_text.hpp"
#include "pilempm/io/output/format.hpp"

namespace pilempm {

std::vector<std::string> split_csv_line(std::string_view line) {
  std::vector<std::string> cells;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = line.find(',', begin);
    cells.emplace_back(
        line.substr(begin, comma == std::string_view::npos ? line.npos : comma - begin));
    if (comma == std::string_view::npos) break;
    begin = comma + 1;
  }
  return cells;
}

std::string table_cell(const NumericTable& t, const std::string& column, const char* format,
                       double scale) {
  if (!t.has(column) || t.rows() == 0) return "-";
  return shown_number(scale * t.column(column).back(), format);
}

NumericTable::NumericTable(std::string source, std::vector<std::string> columns)
    : source_(std::move(source)), columns_(std::move(columns)), values_(columns_.size()) {}

bool NumericTable::has(std::string_view name) const {
  return std::find(columns_.begin(), columns_.end(), name) != columns_.end();
}

const std::vector<double>& NumericTable::column(std::string_view name) const {
  const auto it = std::find(columns_.begin(), columns_.end(), name);
  if (it == columns_.end())
    throw Error(fmt::format("{}: no column \"{}\" (columns: {})", source_, name,
                            fmt::join(columns_, ", ")));
  return values_[static_cast<std::size_t>(it - columns_.begin())];
}

void NumericTable::add_row(const std::vector<double>& row) {
  if (row.size() != columns_.size())
    throw Error(
        fmt::format("{}: a row of {} values for {} columns", source_, row.size(), columns_.size()));
  for (std::size_t i = 0; i < row.size(); ++i) values_[i].push_back(row[i]);
}

NumericTable parse_numeric_csv(std::string_view text, const std::string& source) {
  NumericTable table;
  bool have_header = false;
  std::size_t line_number = 0;
  std::size_t begin = 0;
  std::vector<double> row;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(begin, end - begin);
    begin = end + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty() || line.front() == '#') continue;
    const std::vector<std::string> cells = split_csv_line(line);
    if (!have_header) {
      table = NumericTable(source, cells);
      have_header = true;
      continue;
    }
    if (cells.size() != table.columns().size())
      throw Error(fmt::format("{}:{}: {} cells, the header has {}", source, line_number,
                              cells.size(), table.columns().size()));
    row.clear();
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const std::string& cell = cells[i];
      const std::optional<double> value = whole_number(cell);
      if (!value)
        throw Error(fmt::format("{}:{}: column {}: \"{}\" is not a number", source, line_number,
                                table.columns()[i], cell));
      row.push_back(*value);
    }
    table.add_row(row);
  }
  if (!have_header) throw Error(fmt::format("{}: no header line", source));
  return table;
}

std::string read_csv_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(fmt::format("cannot read {}", path.string()));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

NumericTable read_numeric_csv(const std::filesystem::path& path) {
  return parse_numeric_csv(read_csv_text(path), path.string());
}

}  // namespace pilempm
