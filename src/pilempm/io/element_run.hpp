#pragma once
// Running element tests and writing their results: one test (the single-test commands) or a
// whole case file into an output folder (`pilempm element run`).
#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "pilempm/io/element_case.hpp"
#include "pilempm/io/element_output.hpp"

namespace pilempm {

/// Runs one test and, when it succeeds, writes its curve CSV and JSON summary (an empty path
/// skips that file) and keeps the curve in the record. A model failure (pilempm::Error from the
/// run) is caught and reported in the record; nothing is written then, so older files stay as they
/// were. Errors writing the files are thrown.
ElementRunRecord run_and_write(const ElementCase& element_case,
                               const std::filesystem::path& curve_file,
                               const std::filesystem::path& summary_file,
                               const ProgressCallback& progress = {});

/// Called before and after each test of a run with its position (1-based) and the count.
struct ElementRunObserver {
  std::function<void(std::size_t index, std::size_t total, const ElementCase&)> started;
  std::function<void(std::size_t index, std::size_t total, const ElementRunRecord&)> finished;
};

struct ElementRunReport {
  std::vector<ElementRunRecord> records;
  std::filesystem::path summary_csv, summary_markdown, case_copy;
  std::size_t failures = 0;
  double seconds = 0.0;
};

/// The tests of `file` to run: all of them, or those named in `only` (throws InputError
/// naming the unknown name and listing the known ones).
std::vector<const ElementCase*> select_tests(const ElementCaseFile& file,
                                             const std::vector<std::string>& only);

/// Runs the selected tests of a case into `out_dir`: NAME.csv and NAME.json per test, and
/// summary.csv, summary.md and case.toml (the case text that was run). The folder is checked
/// for writing before the first test starts. A failing test is recorded and the others go on.
ElementRunReport run_element_case(const ElementCaseFile& file, const std::filesystem::path& out_dir,
                                  const std::vector<std::string>& only = {},
                                  const ElementRunObserver& observer = {});

}  // namespace pilempm
