#include "pilempm/io/element_run.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <utility>

#include "pilempm/io/output/atomic_file.hpp"

namespace pilempm {

namespace fs = std::filesystem;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

ElementRunRecord run_and_write(const ElementCase& element_case, const fs::path& curve_file,
                               const fs::path& summary_file, const ProgressCallback& progress) {
  ElementRunRecord record;
  record.test = &element_case;
  const auto start = std::chrono::steady_clock::now();
  ElementResult result;
  try {
    result =
        run_element_test(*element_case.model, element_case.test, element_case.initial, progress);
    record.ok = true;
    record.summary = result.summary;
  } catch (const Error& e) {
    record.error = e.what();
  }
  record.seconds = seconds_since(start);
  if (!record.ok) return record;
  if (!curve_file.empty()) {
    write_file_atomically(curve_file, curve_csv(result.curve));
    record.curve_file = curve_file;
  }
  if (!summary_file.empty()) {
    record.summary_file = summary_file;
    write_file_atomically(summary_file, summary_json(record));
  }
  record.curve = std::move(result.curve);
  return record;
}

std::vector<const ElementCase*> select_tests(const ElementCaseFile& file,
                                             const std::vector<std::string>& only) {
  std::vector<const ElementCase*> selected;
  if (only.empty()) {
    for (const ElementCase& c : file.tests) selected.push_back(&c);
    return selected;
  }
  for (const std::string& name : only) {
    const auto it = std::find_if(file.tests.begin(), file.tests.end(),
                                 [&name](const ElementCase& c) { return c.name == name; });
    if (it == file.tests.end()) {
      std::vector<std::string> names;
      for (const ElementCase& c : file.tests) names.push_back(c.name);
      throw InputError(
          file.source, 0, "--only", name,
          fmt::format("no test of this name; the tests are: {}", fmt::join(names, ", ")));
    }
    if (std::find(selected.begin(), selected.end(), &*it) == selected.end())
      selected.push_back(&*it);
  }
  return selected;
}

ElementRunReport run_element_case(const ElementCaseFile& file, const fs::path& out_dir,
                                  const std::vector<std::string>& only,
                                  const ElementRunObserver& observer) {
  const std::vector<const ElementCase*> selected = select_tests(file, only);
  prepare_output_directory(out_dir);
  ElementRunReport report;
  const auto start = std::chrono::steady_clock::now();
  report.case_copy = out_dir / "case.toml";
  write_file_atomically(report.case_copy, file.text);
  for (std::size_t i = 0; i < selected.size(); ++i) {
    const ElementCase& c = *selected[i];
    if (observer.started) observer.started(i + 1, selected.size(), c);
    report.records.push_back(
        run_and_write(c, out_dir / (c.name + ".csv"), out_dir / (c.name + ".json")));
    if (!report.records.back().ok) ++report.failures;
    if (observer.finished) observer.finished(i + 1, selected.size(), report.records.back());
  }
  report.summary_csv = out_dir / "summary.csv";
  report.summary_markdown = out_dir / "summary.md";
  write_file_atomically(report.summary_csv, summary_table_csv(report.records));
  write_file_atomically(report.summary_markdown,
                        summary_table_markdown(report.records, file.title));
  report.seconds = seconds_since(start);
  return report;
}

}  // namespace pilempm
