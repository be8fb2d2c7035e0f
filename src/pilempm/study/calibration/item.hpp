#pragma once
// What an item of the calibration study works with: the in-memory results of the element tests
// the study ran (summaries and curves, SI, compression positive), and the output of the item (its
// CSV files, its figures, its void-ratio convention). Each item is one function, in a file of its
// own, that returns its section of README.md.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "pilempm/io/element_output.hpp"
#include "pilempm/study/calibration_study.hpp"
#include "pilempm/study/figures.hpp"

namespace pilempm::study::calibration {

/// The element tests of the study by name, as they ran.
class TestResults {
 public:
  explicit TestResults(const std::vector<ElementRunRecord>& records);
  /// The record of a test that succeeded; throws Error for an unknown or failed test.
  const ElementRunRecord& record(std::string_view name) const;
  const ElementCase& test(std::string_view name) const { return *record(name).test; }
  const ElementSummary& summary(std::string_view name) const { return record(name).summary; }
  const std::vector<CurvePoint>& curve(std::string_view name) const { return record(name).curve; }
  /// The cell pressure of a drained triaxial test [Pa]; throws Error for another test.
  double sigma3(std::string_view name) const;

 private:
  const std::vector<ElementRunRecord>& records_;
  std::map<std::string, std::size_t, std::less<>> index_;
};

using Progress = std::function<void(const std::string&)>;

/// The files and figures of one item as it writes them.
class ItemOutput {
 public:
  ItemOutput(std::filesystem::path out_dir, StudyItem& item, Progress progress);
  /// The initial void-ratio convention(s) of the item's tests, in words.
  void set_convention(std::string text) { item_.convention = std::move(text); }
  /// Writes `text` to OUT/`file` (atomically) and lists it as the item's.
  void write_csv(const std::string& file, const std::string& text);
  /// A figure of the item (drawn later from figures.json).
  void add_figure(FigureSpec figure);
  std::vector<FigureSpec>& figures() { return figures_; }

 private:
  std::filesystem::path out_dir_;
  StudyItem& item_;
  Progress progress_;
  std::vector<FigureSpec> figures_;
};

/// An item: writes its files through `out`, adds its structured rows to `report`, returns its
/// section of README.md. Throws Error when a test it needs failed.
using ItemFunction = std::string (*)(const TestResults& tests, ItemOutput& out,
                                     CalibrationStudyReport& report);

std::string oedometer(const TestResults& tests, ItemOutput& out, CalibrationStudyReport& report);
std::string triaxial(const TestResults& tests, ItemOutput& out, CalibrationStudyReport& report);
std::string cyclic_oedometer(const TestResults& tests, ItemOutput& out,
                             CalibrationStudyReport& report);
std::string high_pressure(const TestResults& tests, ItemOutput& out,
                          CalibrationStudyReport& report);
std::string alpha_pressure(const TestResults& tests, ItemOutput& out,
                           CalibrationStudyReport& report);
std::string alpha_sensitivity(const TestResults& tests, ItemOutput& out,
                              CalibrationStudyReport& report);
std::string modified_vs_original(const TestResults& tests, ItemOutput& out,
                                 CalibrationStudyReport& report);
std::string stress_dependent_alpha(const TestResults& tests, ItemOutput& out,
                                   CalibrationStudyReport& report);

}  // namespace pilempm::study::calibration
