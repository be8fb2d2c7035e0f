#pragma once
// Numeric CSV files read back: the element-test curves the study's items are built from
// (format: docs/case-files.md, "Curve CSV"). Lines starting with '#' are comments; the first
// other line is the header; every cell must be a number ("nan" and "inf" included).
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace pilempm {

class NumericTable {
 public:
  NumericTable() = default;
  NumericTable(std::string source, std::vector<std::string> columns);

  const std::string& source() const { return source_; }
  const std::vector<std::string>& columns() const { return columns_; }
  std::size_t rows() const { return values_.empty() ? 0 : values_.front().size(); }
  bool has(std::string_view column) const;
  /// The values of one column; throws Error naming the file and listing the columns.
  const std::vector<double>& column(std::string_view column) const;
  void add_row(const std::vector<double>& row);

 private:
  std::string source_;
  std::vector<std::string> columns_;
  std::vector<std::vector<double>> values_;  ///< by column
};

/// The cells of one CSV line (split at every comma; no quoting, as pilempm writes them).
std::vector<std::string> split_csv_line(std::string_view line);

/// The last value of `column` of `t` written with `format` (shown_number) after scaling, or "-"
/// when the column is missing or empty: a cell of a Markdown table of runs.
std::string table_cell(const NumericTable& t, const std::string& column, const char* format,
                       double scale = 1.0);

/// Parses CSV text; `source` names it in messages ("file:line: ..."). Throws Error.
NumericTable parse_numeric_csv(std::string_view text, const std::string& source);
/// The whole text of a CSV file. Throws Error naming it when it cannot be read.
std::string read_csv_text(const std::filesystem::path& path);
/// Reads and parses a CSV file. Throws Error.
NumericTable read_numeric_csv(const std::filesystem::path& path);

}  // namespace pilempm
