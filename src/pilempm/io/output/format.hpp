#pragma once
// The one set of number and table formatters of every output file (CSV, Markdown, JSON) and of
// the tables printed for a person. The rules, the same everywhere:
//  - a number for a program (CSV, JSON): the shortest text that reads back to the same double,
//    or rounded to a given count of significant digits (printf's %g); a negative zero is
//    written "0";
//  - not-a-number and infinities: "nan", "inf", "-inf" in CSV (every CSV cell is a number that
//    strtod, Python and pandas read back); null in JSON (which has neither); "-" for a person.
//    A value that does not exist (an option that is off, a peak never reached) is an empty CSV
//    cell, written by the caller: that is not a number at all, which NaN is not either;
//  - a number for a person (Markdown, terminal): fixed decimals or a fmt format; "-" when it is
//    not finite.
#include <string>
#include <string_view>
#include <vector>

namespace pilempm {

/// A CSV cell of a number: shortest round trip (`significant_digits` = 0) or %.Ng.
std::string csv_number(double value, int significant_digits = 0);
/// A JSON number: as csv_number, null when not finite.
std::string json_number(double value, int significant_digits = 0);
/// For a person: `decimals` after the point; "-" when not finite.
std::string fixed_number(double value, int decimals);
/// For a person: `value` through the fmt format `format` (e.g. "{:.3g}"); "-" when not finite.
std::string shown_number(double value, std::string_view format);

/// A CSV field: the text as it is, or in double quotes (with " doubled) when it holds a comma,
/// a quote or a line break (RFC 4180).
std::string csv_field(std::string_view text);
/// One CSV line: the fields quoted where needed, separated by commas, ended by a line break.
std::string csv_row(const std::vector<std::string>& cells);

/// A CSV text built row by row: an optional comment line ("# ..."), the header (with the unit
/// of each column in its name), the rows.
class CsvText {
 public:
  CsvText(std::string_view comment, const std::vector<std::string>& header);
  void add(const std::vector<std::string>& row) { text_ += csv_row(row); }
  const std::string& text() const { return text_; }

 private:
  std::string text_;
};

/// A Markdown table cell: '|' escaped, line breaks as spaces.
std::string markdown_cell(std::string_view text);
/// A Markdown table (header, alignment line, rows), each line ended by a line break; the first
/// `left` columns are left-aligned, the others right-aligned.
std::string markdown_table(const std::vector<std::string>& header,
                           const std::vector<std::vector<std::string>>& rows, std::size_t left = 1);

}  // namespace pilempm
