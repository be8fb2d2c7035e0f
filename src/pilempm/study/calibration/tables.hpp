#pragma once
// The tables the items share: the curves of a group of tests in one CSV, the peaks of triaxial
// tests (CSV and Markdown rows), and the initial void-ratio convention of a group in words.
#include <string>
#include <vector>

#include "pilempm/study/calibration/item.hpp"

namespace pilempm::study::calibration {

/// A column of an item's curve CSV: its name (with the unit) and its value at a curve point.
struct CurveColumn {
  std::string name;
  double (*value)(const CurvePoint&);
};
/// Drained triaxial: strains, q (kPa and MPa), p, the principal stresses, e, phi_mob.
const std::vector<CurveColumn>& triaxial_columns();
/// Oedometer: vertical strain and stress, horizontal stress, p, e, rho of the IGS.
const std::vector<CurveColumn>& oedometer_columns();

extern const char* const kCurveComment;     ///< of an oedometer curve CSV
extern const char* const kTriaxialComment;  ///< of a triaxial curve CSV

/// The curves of `names`, one row per increment and test, with what identifies each test; the
/// numbers with as many digits as the tests' own curve files (kCurveDigits).
std::string curves_csv(const TestResults& tests, const std::vector<std::string>& names,
                       const std::vector<CurveColumn>& columns, const char* comment);

/// The peak of each triaxial test `names`: written as the item's CSV `file`; returns the
/// Markdown table (and the blank line after it). `labels` names the rows.
std::string write_peak_table(const TestResults& tests, ItemOutput& out, const std::string& file,
                             const std::vector<std::string>& names,
                             const std::vector<std::string>& labels);

/// "0.68 (at p = 0)" or "0.68 (at initial stress)".
std::string e0_text(const ElementCase& c);
std::string convention_name(VoidRatioConvention c);
/// The convention(s) the tests `names` used, in words, with the range of e at the start.
std::string convention_of(const TestResults& tests, const std::vector<std::string>& names);

}  // namespace pilempm::study::calibration
