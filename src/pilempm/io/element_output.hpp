#pragma once
// Output of element tests: the curve of one test as CSV, its summary as JSON, and the summary
// table of a whole case (CSV, Markdown, and aligned text for the terminal). Curves are
// compression positive with the unit in every column name (docs/case-files.md lists them).
// Files are written atomically: into FILE.<unique>.tmp in the same folder, then renamed over FILE,
// so an error never leaves a half-written file and never destroys a good older one.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "pilempm/element/element_tests.hpp"
#include "pilempm/io/element_case.hpp"

namespace pilempm {

/// Writes `content` to a new temporary file next to `path` (temporary_path_for), then renames it
/// over `path`. Throws Error (and removes the temporary file) when anything fails, a full disk
/// included; `path` is then untouched.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);
/// A name for a temporary file next to `path` that no other write uses, not even one of another
/// process or thread into the same folder: FILE.<process>-<count>.tmp.
std::filesystem::path temporary_path_for(const std::filesystem::path& path);

/// Creates the folder if needed and checks that a file can be created in it (throws Error).
void prepare_output_directory(const std::filesystem::path& directory);
/// Checks that the folder of an output file exists and is writable (throws Error).
void check_output_file(const std::filesystem::path& file);

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
