// The calibration study: runs the element tests of its case, then each item (one file each
// under study/calibration/) on their results in memory, then the figures and README.md.
#include "pilempm/study/calibration_study.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <tuple>
#include <type_traits>
#include <utility>
#include <variant>

#include "pilempm/core/error.hpp"
#include "pilempm/io/element_run.hpp"
#include "pilempm/io/output/atomic_file.hpp"
#include "pilempm/study/calibration/item.hpp"
#include "pilempm/study/calibration/readme.hpp"
#include "pilempm/study/calibration/study_tests.hpp"
#include "pilempm/study/figures.hpp"
#include "pilempm/study/study_calibration_case.hpp"  // generated from examples/study_calibration.toml

namespace pilempm {

namespace fs = std::filesystem;

namespace {

namespace cal = study::calibration;

constexpr int kQuickDivisor = 4;

struct ItemSpec {
  const char* key;    // short name, also the stem of its files
  const char* title;  // heading in README.md
  cal::ItemFunction function;
};

const std::vector<ItemSpec> kItems = {
    {"oedometer", "Oedometer: void ratio against vertical stress", &cal::oedometer},
    {"triaxial", "Drained triaxial compression: the calibration tests", &cal::triaxial},
    {"cyclic_oedometer", "Cyclic oedometer with and without intergranular strain",
     &cal::cyclic_oedometer},
    {"high_pressure", "High-pressure triaxial compression beside Bolton (1986)",
     &cal::high_pressure},
    {"alpha_pressure", "The exponent alpha against pressure (Herle & Gudehus 1999)",
     &cal::alpha_pressure},
    {"alpha_sensitivity", "Triaxial at 6 MPa for several alpha", &cal::alpha_sensitivity},
    {"modified_vs_original", "Modified against original set at 10 MPa and 0.1 MPa",
     &cal::modified_vs_original},
    {"stress_dependent_alpha", "The stress-dependent alpha option (beyond the study)",
     &cal::stress_dependent_alpha},
};

class Study {
 public:
  Study(const fs::path& out_dir, const CalibrationStudyOptions& options, cal::Progress progress)
      : options_(options), progress_(std::move(progress)) {
    report_.out_dir = out_dir.empty() ? fs::path(".") : out_dir;
    report_.tests_dir = report_.out_dir / "tests";
    report_.readme = report_.out_dir / "README.md";
    report_.figures_json = report_.out_dir / "figures.json";
    report_.plot_script = report_.out_dir / "plot_figures.py";
    report_.quick = options.quick;
    report_.plots_requested = options.plots;
  }

  CalibrationStudyReport run() {
    const auto start = std::chrono::steady_clock::now();
    prepare_output_directory(report_.out_dir);
    ElementCaseFile file = calibration_study_case();
    if (options_.quick) reduce_increments(file, kQuickDivisor);
    const ElementRunReport run = run_tests(file);
    const cal::TestResults tests(run.records);

    std::vector<FigureSpec> figures;
    std::vector<std::string> bodies;
    for (std::size_t i = 0; i < kItems.size(); ++i) {
      StudyItem item;
      item.key = kItems[i].key;
      item.title = kItems[i].title;
      say(fmt::format("item {}/{}: {}", i + 1, kItems.size(), item.title));
      cal::ItemOutput out(report_.out_dir, item, progress_);
      std::string body;
      try {
        body = kItems[i].function(tests, out, report_);
        for (FigureSpec& f : out.figures()) figures.push_back(std::move(f));
      } catch (const Error& e) {
        item.ok = false;
        item.error = e.what();
        item.png.clear();
        say(fmt::format("item {} FAILED: {}", item.key, item.error));
      }
      bodies.push_back(std::move(body));
      report_.items.push_back(std::move(item));
    }

    write_file_atomically(report_.plot_script, plot_script_text());
    write_file_atomically(report_.figures_json, figures_json(figures));
    say(fmt::format("wrote {} and {}", report_.figures_json.string(),
                    report_.plot_script.string()));
    draw(figures);
    write_file_atomically(report_.readme, cal::study_readme(report_, bodies));
    say(fmt::format("wrote {}", report_.readme.string()));
    report_.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return std::move(report_);
  }

 private:
  const CalibrationStudyOptions& options_;
  cal::Progress progress_;
  CalibrationStudyReport report_;

  void say(const std::string& line) const {
    if (progress_) progress_(line);
  }

  ElementRunReport run_tests(const ElementCaseFile& file) {
    const std::vector<std::string> names = calibration_study_test_names();
    say(fmt::format("{} element tests{} -> {}/", names.size(),
                    options_.quick ? " (quick: a quarter of the increments)" : "",
                    report_.tests_dir.string()));
    for (const std::string& name : names)
      if (std::none_of(file.tests.begin(), file.tests.end(),
                       [&name](const ElementCase& c) { return c.name == name; }))
        throw Error(fmt::format("{}: no test \"{}\"; the study finds its series by name",
                                file.source, name));
    ElementRunObserver observer;
    const int digits = static_cast<int>(std::to_string(names.size()).size());
    observer.finished = [this, digits](std::size_t index, std::size_t total,
                                       const ElementRunRecord& r) {
      say(r.ok ? fmt::format("[{:>{}}/{}] {} {:.2f} s", index, digits, total, r.test->name,
                             r.seconds)
               : fmt::format("[{:>{}}/{}] {} FAILED: {}", index, digits, total, r.test->name,
                             r.error));
    };
    ElementRunReport run = run_element_case(file, report_.tests_dir, names, observer);
    report_.tests_run = run.records.size();
    report_.tests_failed = run.failures;
    return run;
  }

  void draw(const std::vector<FigureSpec>& figures) {
    // Old figures never stay beside new data: remove them first.
    for (const FigureSpec& f : figures) {
      std::error_code ignored;
      fs::remove(report_.out_dir / f.file, ignored);
    }
    if (!options_.plots) {
      report_.plots.problem = "plotting was switched off (--no-plots)";
      return;
    }
    say("plotting with the script " + report_.plot_script.string());
    report_.plots = draw_figures(report_.plot_script, report_.figures_json, options_.python,
                                 [this](const std::string& line) { say("  " + line); });
  }
};

}  // namespace

std::vector<std::string> CalibrationStudyReport::csv_files() const {
  std::vector<std::string> files;
  for (const StudyItem& item : items) files.insert(files.end(), item.csv.begin(), item.csv.end());
  return files;
}

std::vector<std::string> CalibrationStudyReport::png_files() const {
  std::vector<std::string> files;
  for (const StudyItem& item : items) files.insert(files.end(), item.png.begin(), item.png.end());
  return files;
}

std::size_t CalibrationStudyReport::failed_items() const {
  std::size_t n = 0;
  for (const StudyItem& item : items) n += item.ok ? 0 : 1;
  return n;
}

std::string_view calibration_study_case_text() {
  return {reinterpret_cast<const char*>(generated::kStudyCalibrationCase),
          sizeof generated::kStudyCalibrationCase};
}

ElementCaseFile calibration_study_case() {
  return parse_element_case(std::string(calibration_study_case_text()), kCalibrationStudyCaseName);
}

std::vector<std::string> calibration_study_test_names() {
  return cal::study_test_names();
}

void reduce_increments(ElementCaseFile& file, int divisor) {
  if (divisor < 1) throw InvalidValue("divisor", std::to_string(divisor), ">= 1");
  const auto reduce = [divisor](int steps, int minimum) {
    return std::max(std::min(steps, minimum), steps / divisor);
  };
  for (ElementCase& c : file.tests) {
    std::visit(
        [&reduce](auto& t) {
          using T = std::decay_t<decltype(t)>;
          if constexpr (std::is_same_v<T, OedometerTest>)
            t.steps_per_segment = reduce(t.steps_per_segment, 25);
          else if constexpr (std::is_same_v<T, StrainPathTest>)
            for (auto& s : t.segments) s.steps = reduce(s.steps, 25);
          else
            t.steps = reduce(t.steps, 100);
        },
        c.test);
  }
}

CalibrationStudyReport run_calibration_study(
    const fs::path& out_dir, const CalibrationStudyOptions& options,
    const std::function<void(const std::string&)>& progress) {
  return Study(out_dir, options, progress).run();
}

}  // namespace pilempm
