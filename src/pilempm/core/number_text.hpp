#pragma once
// A number read from a piece of text: the readers of pilempm's own tab- and comma-separated
// records (checkpoint rows, CSV tables, laboratory data) share one rule for what counts.
#include <optional>
#include <string_view>

namespace pilempm {

/// The number that the whole of `text` is, as strtod reads it (decimal or exponent notation,
/// also "nan" and "inf", which the writers use for missing values; white space before it is
/// skipped, as "1, 2" has it), or nothing when `text` is empty, has anything after the number,
/// or is no number. Out-of-range magnitudes
/// read as strtod gives them (±inf, or 0 and subnormals); range checks are the caller's
/// (NumberRange).
std::optional<double> whole_number(std::string_view text);

/// `value` as it reads back from its decimal text with `digits` significant digits (1 to 17):
/// the number a person would write, e.g. 1e-6 for 100 * (1e-4)^2 = 1.0000000000000002e-06.
double with_significant_digits(double value, int digits);

}  // namespace pilempm
