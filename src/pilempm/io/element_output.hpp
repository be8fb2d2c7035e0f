#pragma once
// Output of element tests: the curve of one test as CSV, its summary as JSON, and the summary
// table of a whole case (CSV, Markdown, and aligned text for the terminal). Curves are
// compression positive with the unit in every column name (docs/case-files.md lists them).
// The texts only: io/output/atomic_file.hpp writes them.
#include <filesystem>
#include <string>
#include <vector>

#include "pilempm/element/element_tests.hpp"
#include "pilempm/io/element_case.hpp"

namespace pilempm {

/// Significant digits of the numbers of curve_csv and of the summaries.
inline constexpr int kCurveDigits = 10;

/// The column names of curve_csv, in order.
const std::vector<std::string>& curve_columns();
/// A curve as CSV: one comment line ("# ..." saying the sign convention), the header, the rows.
std::string curve_csv(const std::vector<CurvePoint>& curve);

/// The outcome of one test of a run.
struct ElementRunRecord {
  const ElementCase* test = nullptr;
  bool ok = false;
  ElementSummary summary{};
  double seconds = 0.0;
  std::string error;                   ///< why it failed (empty when ok)
  std::vector<CurvePoint> curve;       ///< the curve (SI, compression positive) when ok
  std::filesystem::path curve_file;    ///< where the curve went (empty: not written)
  std::filesystem::path summary_file;  ///< where the JSON summary went (empty: not written)
};

/// The JSON summary of one test: what was run (material, IGS, e0 and its convention, the
/// programme in the case file's units) and what came out (initial void ratio actually used,
/// peak, dilatancy, final state, integrator statistics).
std::string summary_json(const ElementRunRecord& record);

/// The summary table of a run, one row per test.
std::string summary_table_csv(const std::vector<ElementRunRecord>& records);
std::string summary_table_markdown(const std::vector<ElementRunRecord>& records,
                                   const std::string& title);
std::string summary_table_text(const std::vector<ElementRunRecord>& records);

}  // namespace pilempm
