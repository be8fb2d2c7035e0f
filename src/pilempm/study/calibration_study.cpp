#include "pilempm/study/calibration_study.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <set>
#include <tuple>
#include <type_traits>
#include <utility>
#include <variant>

#include "pilempm/core/error.hpp"
#include "pilempm/io/element_output.hpp"
#include "pilempm/io/element_run.hpp"
#include "pilempm/study/csv_table.hpp"
#include "pilempm/study/figures.hpp"
#include "pilempm/study/study_calibration_case.hpp"  // generated from examples/study_calibration.toml

#include "pilempm/io/text_escaping.hpp"

namespace pilempm {

namespace fs = std::filesystem;

namespace {

constexpr double kKPa = 1.0e3;
constexpr double kMPa = 1.0e6;
constexpr int kQuickDivisor = 4;
// Bolton's table of the study (BRIEF.md §4): R_D = 95 % of the high-pressure series, phi_c of
// the original set.
constexpr double kBoltonRelativeDensity = 0.95;
constexpr double kBoltonPhiC = 31.0;
// The stress-dependent alpha option should match the sets within this (issue 3).
constexpr double kStressDependentTolerance = 1.0;  // [deg]

// ---- The tests of the study, by name (examples/study_calibration.toml) ----------------------

const std::vector<std::string> kOedometerSets = {"original", "loose-fit"};
const std::vector<std::string> kOedometerE0 = {"0.657", "0.70", "0.75", "0.80", "0.823"};
const std::vector<std::string> kTriaxialDense = {
    "tx-dense-s3-50kPa-e0.59", "tx-dense-s3-100kPa-e0.60", "tx-dense-s3-200kPa-e0.60"};
const std::vector<std::string> kTriaxialLoose = {
    "tx-loose-s3-50kPa-e0.70", "tx-loose-s3-100kPa-e0.84", "tx-loose-s3-200kPa-e0.81"};
const std::vector<std::string> kTriaxialDeltares = {"tx-s3-200kPa-e0.67", "tx-s3-200kPa-e0.75"};
const std::vector<std::string> kCyclic = {"oed-cyclic-IGS1", "oed-cyclic-IGS2", "oed-cyclic-IGS3",
                                          "oed-cyclic-IGS4", "oed-cyclic-no-IGS"};
const std::string kCyclicReference = "oed-cyclic-no-IGS";
const std::vector<std::string> kHighPressure = {"tx-hp-s3-0.5MPa", "tx-hp-s3-2MPa",
                                                "tx-hp-s3-4MPa",   "tx-hp-s3-6MPa",
                                                "tx-hp-s3-16MPa",  "tx-hp-s3-30MPa"};
const std::vector<std::string> kAlphaSensitivity = {"tx-alpha0.03-s3-6MPa", "tx-alpha0.06-s3-6MPa",
                                                    "tx-hp-s3-6MPa", "tx-alpha0.2-s3-6MPa"};
// Item 7 and 8: {low pressure, high pressure} of each set.
const std::pair<std::string, std::string> kOriginal = {"tx-original-s3-0.1MPa-e0.68",
                                                       "tx-original-s3-10MPa-e0.68"};
const std::pair<std::string, std::string> kModified = {"tx-modified-s3-0.1MPa-e0.68",
                                                       "tx-modified-s3-10MPa-e0.68"};
const std::pair<std::string, std::string> kStressDependent = {"tx-stress-dependent-s3-0.1MPa-e0.68",
                                                              "tx-stress-dependent-s3-10MPa-e0.68"};
// alpha(p): the void ratios of the study and the pressures of the README table.
const std::vector<double> kAlphaVoidRatios = {0.68, 0.75};
const std::vector<double> kAlphaTablePressuresKPa = {10,   20,   50,   100,   200,   500,
                                                     1000, 2000, 5000, 10000, 20000, 30000};

std::string oedometer_name(const std::string& set, const std::string& e0) {
  return "oed-" + set + "-e" + e0;  // e.g. oed-original-e0.657
}

std::vector<std::string> joined(std::initializer_list<std::vector<std::string>> lists) {
  std::vector<std::string> all;
  for (const auto& list : lists) all.insert(all.end(), list.begin(), list.end());
  return all;
}

// ---- Formatting -----------------------------------------------------------------------------

std::string fixed(double value, int digits) {
  if (!std::isfinite(value)) return "-";
  return fmt::format("{:.{}f}", value + 0.0, digits);
}

// A number for CSV: shortest round-trip text; empty for NaN (a gap).
std::string csv_number(double value) {
  if (std::isnan(value)) return "";
  return fmt::format("{}", value + 0.0);
}

// A CSV text built row by row; the header has the unit of each column in its name.
class CsvText {
 public:
  CsvText(const std::string& comment, const std::vector<std::string>& header) {
    if (!comment.empty()) text_ = "# " + comment + "\n";
    add(header);
  }
  void add(const std::vector<std::string>& row) {
    for (std::size_t i = 0; i < row.size(); ++i) {
      if (i > 0) text_ += ',';
      text_ += csv_field(row[i]);
    }
    text_ += '\n';
  }
  const std::string& text() const { return text_; }

 private:
  std::string text_;
};

std::string markdown_cell(const std::string& text) {
  std::string out;
  for (char ch : text) {
    if (ch == '|') out += '\\';
    out += ch == '\n' ? ' ' : ch;
  }
  return out;
}

// A Markdown table; the first `left` columns are left-aligned, the others right-aligned.
std::string markdown_table(const std::vector<std::string>& header,
                           const std::vector<std::vector<std::string>>& rows,
                           std::size_t left = 1) {
  std::string out = "|";
  for (const auto& h : header) out += " " + markdown_cell(h) + " |";
  out += "\n|";
  for (std::size_t i = 0; i < header.size(); ++i) out += i < left ? " --- |" : " ---: |";
  out += '\n';
  for (const auto& row : rows) {
    out += '|';
    for (const auto& cell : row) out += " " + markdown_cell(cell) + " |";
    out += '\n';
  }
  return out + "\n";
}

std::string color(std::size_t index) {
  return fmt::format("C{}", index % 10);
}

std::string convention_name(VoidRatioConvention c) {
  return std::string(to_string(c));
}

// ---- Curves of the item CSVs -----------------------------------------------------------------

// A column of an item CSV taken from a test's curve CSV: renamed and scaled.
struct ColumnPick {
  std::string source;  // column of the curve CSV
  std::string name;    // column of the item CSV (with its unit)
  double scale = 1.0;
};

const std::vector<ColumnPick> kTriaxialColumns = {
    {"axial_strain_pct", "axial_strain_pct"},
    {"volumetric_strain_pct", "volumetric_strain_pct"},
    {"q_kPa", "q_kPa"},
    {"q_kPa", "q_MPa", 1.0e-3},
    {"p_kPa", "p_kPa"},
    {"sigma_a_kPa", "sigma_1_kPa"},
    {"sigma_r_kPa", "sigma_3_kPa"},
    {"void_ratio", "void_ratio"},
    {"phi_mob_deg", "phi_mob_deg"}};
const std::vector<ColumnPick> kOedometerColumns = {{"axial_strain_pct", "vertical_strain_pct"},
                                                   {"sigma_a_kPa", "sigma_v_kPa"},
                                                   {"sigma_r_kPa", "sigma_h_kPa"},
                                                   {"p_kPa", "p_kPa"},
                                                   {"void_ratio", "void_ratio"},
                                                   {"igs_rho", "igs_rho"}};

constexpr const char* kCurveComment =
    "pilempm study calibration: one row per increment and test; compression positive; strains "
    "logarithmic, in percent; e0_at: the convention of e0, initial_void_ratio: the void ratio "
    "actually used at the start";
constexpr const char* kTriaxialComment =
    "pilempm study calibration: drained triaxial compression at constant cell pressure, one row "
    "per increment and test; compression positive (volumetric strain > 0 is contraction); "
    "strains logarithmic, in percent; q = sigma_1 - sigma_3; e0_at: the convention of e0, "
    "initial_void_ratio: the void ratio actually used at the start";

SeriesSpec curve_series(const std::string& csv, const std::string& test, const std::string& x,
                        const std::string& y, const std::string& label, const std::string& colour,
                        const std::string& linestyle = "-", double linewidth = 1.6) {
  SeriesSpec s;
  s.csv = csv;
  s.where = {{"test", test}};
  s.x = x;
  s.y = y;
  s.label = label;
  s.style.color = colour;
  s.style.linestyle = linestyle;
  s.style.linewidth = linewidth;
  return s;
}

// Axis labels (matplotlib mathtext between $...$).
const std::string kAxialStrainLabel = "axial strain $\\varepsilon_1$ [%]";
const std::string kVolumetricStrainLabel = "volumetric strain $\\varepsilon_v$ [%] (contraction +)";
const std::string kDeviatorKPaLabel = "deviator stress $q = \\sigma'_1 - \\sigma'_3$ [kPa]";
const std::string kDeviatorMPaLabel = "deviator stress $q = \\sigma'_1 - \\sigma'_3$ [MPa]";

// ---- The study --------------------------------------------------------------------------------

class Study {
 public:
  Study(const fs::path& out_dir, const CalibrationStudyOptions& options,
        const std::function<void(const std::string&)>& progress)
      : options_(options), progress_(progress) {
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
    file_ = calibration_study_case();
    if (options_.quick) reduce_increments(file_, kQuickDivisor);
    run_tests();

    using ItemFunction = std::string (Study::*)(StudyItem&);
    const std::vector<std::tuple<std::string, std::string, ItemFunction>> items = {
        {"oedometer", "Oedometer: void ratio against vertical stress", &Study::oedometer},
        {"triaxial", "Drained triaxial compression: the calibration tests", &Study::triaxial},
        {"cyclic_oedometer", "Cyclic oedometer with and without intergranular strain",
         &Study::cyclic_oedometer},
        {"high_pressure", "High-pressure triaxial compression beside Bolton (1986)",
         &Study::high_pressure},
        {"alpha_pressure", "The exponent alpha against pressure (Herle & Gudehus 1999)",
         &Study::alpha_pressure},
        {"alpha_sensitivity", "Triaxial at 6 MPa for several alpha", &Study::alpha_sensitivity},
        {"modified_vs_original", "Modified against original set at 10 MPa and 0.1 MPa",
         &Study::modified_vs_original},
        {"stress_dependent_alpha", "The stress-dependent alpha option (beyond the study)",
         &Study::stress_dependent_alpha},
    };
    for (std::size_t i = 0; i < items.size(); ++i) {
      const auto& [key, title, function] = items[i];
      StudyItem item;
      item.key = key;
      item.title = title;
      say(fmt::format("item {}/{}: {}", i + 1, items.size(), title));
      pending_figures_.clear();
      std::string body;
      try {
        body = (this->*function)(item);
        for (FigureSpec& f : pending_figures_) figures_.push_back(std::move(f));
      } catch (const Error& e) {
        item.ok = false;
        item.error = e.what();
        item.png.clear();
        say(fmt::format("item {} FAILED: {}", key, item.error));
      }
      item_bodies_.push_back(std::move(body));
      report_.items.push_back(std::move(item));
    }

    write_file_atomically(report_.plot_script, plot_script_text());
    write_file_atomically(report_.figures_json, figures_json(figures_));
    say(fmt::format("wrote {} and {}", report_.figures_json.string(),
                    report_.plot_script.string()));
    draw();
    write_file_atomically(report_.readme, readme());
    say(fmt::format("wrote {}", report_.readme.string()));
    report_.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return std::move(report_);
  }

 private:
  const CalibrationStudyOptions& options_;
  const std::function<void(const std::string&)>& progress_;
  CalibrationStudyReport report_;
  ElementCaseFile file_;
  ElementRunReport run_;
  std::map<std::string, std::size_t, std::less<>> index_;
  std::map<std::string, NumericTable, std::less<>> curves_;
  std::vector<FigureSpec> figures_, pending_figures_;
  std::vector<std::string> item_bodies_;

  void say(const std::string& line) const {
    if (progress_) progress_(line);
  }

  // ---- Running the element tests

  void run_tests() {
    const std::vector<std::string> names = calibration_study_test_names();
    say(fmt::format("{} element tests{} -> {}/", names.size(),
                    options_.quick ? " (quick: a quarter of the increments)" : "",
                    report_.tests_dir.string()));
    for (const std::string& name : names)
      if (std::none_of(file_.tests.begin(), file_.tests.end(),
                       [&name](const ElementCase& c) { return c.name == name; }))
        throw Error(fmt::format("{}: no test \"{}\"; the study finds its series by name",
                                file_.source, name));
    ElementRunObserver observer;
    const int digits = static_cast<int>(std::to_string(names.size()).size());
    observer.finished = [this, digits](std::size_t index, std::size_t total,
                                       const ElementRunRecord& r) {
      say(r.ok ? fmt::format("[{:>{}}/{}] {} {:.2f} s", index, digits, total, r.test->name,
                             r.seconds)
               : fmt::format("[{:>{}}/{}] {} FAILED: {}", index, digits, total, r.test->name,
                             r.error));
    };
    run_ = run_element_case(file_, report_.tests_dir, names, observer);
    for (std::size_t i = 0; i < run_.records.size(); ++i)
      index_.emplace(run_.records[i].test->name, i);
    report_.tests_run = run_.records.size();
    report_.tests_failed = run_.failures;
  }

  const ElementRunRecord& record(const std::string& name) const {
    const auto it = index_.find(name);
    if (it == index_.end()) throw Error(fmt::format("the study's case has no test \"{}\"", name));
    const ElementRunRecord& r = run_.records[it->second];
    if (!r.ok) throw Error(fmt::format("element test {} failed: {}", name, r.error));
    return r;
  }
  const ElementCase& test(const std::string& name) const { return *record(name).test; }

  const NumericTable& curve(const std::string& name) {
    const auto it = curves_.find(name);
    if (it != curves_.end()) return it->second;
    return curves_.emplace(name, read_numeric_csv(record(name).curve_file)).first->second;
  }

  double sigma3(const std::string& name) const {
    const auto* t = std::get_if<DrainedTriaxialTest>(&test(name).test);
    if (t == nullptr) throw Error(fmt::format("study test {} is not a drained triaxial", name));
    return t->sigma3;
  }

  // ---- Files of the items

  void write_csv(StudyItem& item, const std::string& file, const std::string& text) {
    write_file_atomically(report_.out_dir / file, text);
    item.csv.push_back(file);
    say(fmt::format("  wrote {}", (report_.out_dir / file).string()));
  }

  void add_figure(StudyItem& item, FigureSpec figure) {
    item.png.push_back(figure.file);
    pending_figures_.push_back(std::move(figure));
  }

  // The curves of `names`, one row per increment and test, with what identifies each test.
  std::string curves_csv(const std::vector<std::string>& names,
                         const std::vector<ColumnPick>& picks, const char* comment) {
    std::vector<std::string> header = {"test", "set", "igs", "e0", "e0_at", "initial_void_ratio"};
    for (const ColumnPick& p : picks) header.push_back(p.name);
    CsvText csv(comment, header);
    for (const std::string& name : names) {
      const ElementRunRecord& r = record(name);
      const ElementCase& c = *r.test;
      const NumericTable& table = curve(name);
      std::vector<const std::vector<double>*> columns;
      for (const ColumnPick& p : picks) columns.push_back(&table.column(p.source));
      const std::vector<std::string> identity = {c.name,
                                                 c.material.name,
                                                 c.igs ? c.igs->name : "none",
                                                 format_value(c.initial.e0),
                                                 convention_name(c.initial.e0_at),
                                                 csv_number(r.summary.initial_void_ratio)};
      for (std::size_t row = 0; row < table.rows(); ++row) {
        std::vector<std::string> cells = identity;
        for (std::size_t k = 0; k < picks.size(); ++k)
          cells.push_back(csv_number((*columns[k])[row] * picks[k].scale));
        csv.add(cells);
      }
    }
    return csv.text();
  }

  // The peak of each triaxial test: CSV text and Markdown rows. `labels` names the rows.
  struct PeakTable {
    std::string csv;
    std::vector<std::vector<std::string>> rows;
  };
  PeakTable peak_table(const std::vector<std::string>& names,
                       const std::vector<std::string>& labels) {
    CsvText csv(
        "pilempm study calibration: peak of q of each drained triaxial test; compression "
        "positive; psi after Schanz & Vermeer from d eps_v/d eps_1 at the peak; peak_at_end = "
        "true: q still rose at the end (no peak)",
        {"test", "series", "set", "sigma3_kPa", "e0", "e0_at", "initial_void_ratio", "peak_q_kPa",
         "axial_strain_at_peak_pct", "phi_peak_deg", "dilatancy_ratio_at_peak", "psi_peak_deg",
         "peak_at_end"});
    PeakTable table;
    for (std::size_t i = 0; i < names.size(); ++i) {
      const ElementRunRecord& r = record(names[i]);
      const ElementCase& c = *r.test;
      const ElementSummary& s = r.summary;
      csv.add({c.name, labels[i], c.material.name, csv_number(sigma3(names[i]) / kKPa),
               format_value(c.initial.e0), convention_name(c.initial.e0_at),
               csv_number(s.initial_void_ratio), csv_number(s.peak_q / kKPa),
               csv_number(100.0 * s.axial_strain_at_peak), csv_number(s.phi_at_peak_deg),
               csv_number(s.dilatancy_ratio_at_peak), csv_number(s.psi_at_peak_deg),
               s.peak_at_end ? "true" : "false"});
      table.rows.push_back({labels[i], c.material.name,
                            fmt::format("{:g}", sigma3(names[i]) / kKPa), e0_text(c),
                            fixed(s.initial_void_ratio, 4),
                            fmt::format("{:.6g}{}", s.peak_q / kKPa, s.peak_at_end ? " (end)" : ""),
                            fixed(100.0 * s.axial_strain_at_peak, 2), fixed(s.phi_at_peak_deg, 2),
                            fixed(s.psi_at_peak_deg, 2)});
    }
    table.csv = csv.text();
    return table;
  }
  static const std::vector<std::string>& peak_header() {
    static const std::vector<std::string> header = {"series",          "set",        "σ3 [kPa]",
                                                    "e0 (convention)", "e at start", "peak q [kPa]",
                                                    "ε1 at peak [%]",  "φ peak [°]", "ψ peak [°]"};
    return header;
  }

  static std::string e0_text(const ElementCase& c) {
    return fmt::format("{} ({})", format_value(c.initial.e0),
                       c.initial.e0_at == VoidRatioConvention::at_zero_pressure
                           ? "at p = 0"
                           : "at initial stress");
  }

  // The convention(s) the tests of an item used, in words.
  std::string convention_of(const std::vector<std::string>& names) const {
    std::set<VoidRatioConvention> used;
    double e_lo = 1e9, e_hi = -1e9;
    for (const std::string& name : names) {
      used.insert(test(name).initial.e0_at);
      e_lo = std::min(e_lo, record(name).summary.initial_void_ratio);
      e_hi = std::max(e_hi, record(name).summary.initial_void_ratio);
    }
    const std::string range =
        e_lo == e_hi ? fixed(e_lo, 4) : fmt::format("{} … {}", fixed(e_lo, 4), fixed(e_hi, 4));
    if (used.size() == 1 && *used.begin() == VoidRatioConvention::at_initial_stress)
      return fmt::format(
          "`initial-stress`: e0 is the void ratio at the initial stress of each test, used as "
          "it is (e at the start: {})",
          range);
    if (used.size() == 1)
      return fmt::format(
          "`zero-pressure`: e0 is a reference at p = 0, scaled to the initial mean stress by "
          "Bauer's law e = e0 exp[−(3p0/h_s)^n], as the soilmodels.info UMAT and PLAXIS do (e at "
          "the start: {})",
          range);
    return fmt::format("mixed: each test's convention is in its row (e at the start: {})", range);
  }

  static std::string image(const std::string& file, const std::string& alt) {
    return fmt::format("![{}]({})\n\n", alt, file);
  }

  // ---- Item 1: oedometer

  std::string oedometer(StudyItem& item) {
    std::vector<std::string> names;
    for (const auto& set : kOedometerSets)
      for (const auto& e0 : kOedometerE0) names.push_back(oedometer_name(set, e0));
    item.convention = convention_of(names);
    write_csv(item, "oedometer.csv", curves_csv(names, kOedometerColumns, kCurveComment));

    FigureSpec fig;
    fig.file = "oedometer.png";
    fig.title = "Oedometer (1D compression), original parameters with h_s = 4 GPa and 2 GPa";
    fig.cols = 2;
    fig.width_in = 12.0;
    fig.height_in = 5.0;
    fig.sharey = true;
    fig.shared_legend = true;  // the same initial void ratios in both panels
    fig.legend_columns = static_cast<int>(kOedometerE0.size());
    std::vector<std::string> header = {"e0 (at σ'_v0)"};
    std::vector<std::vector<std::string>> rows(kOedometerE0.size());
    for (std::size_t s = 0; s < kOedometerSets.size(); ++s) {
      const ElementCase& first = test(oedometer_name(kOedometerSets[s], kOedometerE0[0]));
      const double h_s = first.material.hypoplastic().h_s;
      const double sigma_end = record(first.name).summary.final.axial_stress;
      PanelSpec panel;
      panel.title = fmt::format("$h_s$ = {:g} GPa (set {})", h_s / 1e9, first.material.name);
      panel.x = {"vertical effective stress $\\sigma'_v$ [kPa] (log scale)", true, {}};
      panel.y = {"void ratio e [-]", false, {}};
      header.push_back(fmt::format("e at {:g} kPa, h_s = {:g} GPa", sigma_end / kKPa, h_s / 1e9));
      header.push_back(fmt::format("Δe, h_s = {:g} GPa", h_s / 1e9));
      for (std::size_t k = 0; k < kOedometerE0.size(); ++k) {
        const std::string name = oedometer_name(kOedometerSets[s], kOedometerE0[k]);
        const ElementRunRecord& r = record(name);
        panel.series.push_back(curve_series(
            "oedometer.csv", name, "sigma_v_kPa", "void_ratio",
            "initial void ratio $e_0$ = " + format_value(r.test->initial.e0), color(k)));
        if (s == 0) rows[k].push_back(format_value(r.test->initial.e0));
        rows[k].push_back(fixed(r.summary.final.void_ratio, 4));
        rows[k].push_back(fixed(r.summary.final.void_ratio - r.summary.initial_void_ratio, 4));
      }
      fig.panels.push_back(std::move(panel));
    }
    add_figure(item, std::move(fig));
    const OedometerTest& programme = std::get<OedometerTest>(test(names[0]).test);
    std::string md = fmt::format(
        "One-dimensional compression from σ'_v0 = {:g} kPa (σ'_h0 = K0 σ'_v0, K0 = {:g}) to "
        "{:g} kPa, intergranular strain {}, for the dense to loose initial void ratios of the "
        "study, with the "
        "original set (h_s = 4 GPa) and the loose-fit set (h_s = 2 GPa, otherwise equal). The "
        "softer h_s compresses every sample more.\n\n",
        programme.sigma_v0 / kKPa, programme.K0, programme.sigma_v_targets.back() / kKPa,
        test(names[0]).igs ? test(names[0]).igs->name : "none");
    md += image("oedometer.png", "oedometer curves");
    md += markdown_table(header, rows);
    return md;
  }

  // ---- Item 2: drained triaxial

  std::string triaxial(StudyItem& item) {
    const std::vector<std::pair<std::string, std::vector<std::string>>> groups = {
        {"dense", kTriaxialDense}, {"loose", kTriaxialLoose}, {"Deltares", kTriaxialDeltares}};
    const std::vector<std::string> names =
        joined({kTriaxialDense, kTriaxialLoose, kTriaxialDeltares});
    item.convention = convention_of(names);
    write_csv(item, "triaxial.csv", curves_csv(names, kTriaxialColumns, kTriaxialComment));

    FigureSpec fig;
    fig.file = "triaxial.png";
    fig.title = fmt::format("Drained triaxial compression, set {}, intergranular strain {}",
                            test(names[0]).material.name,
                            test(names[0]).igs ? test(names[0]).igs->name : "none");
    fig.rows = 2;
    fig.cols = 3;
    fig.width_in = 15.0;
    fig.height_in = 8.5;
    fig.sharex = true;
    std::vector<PanelSpec> q_panels, v_panels;
    std::vector<std::string> labels;
    for (const auto& [group, members] : groups) {
      PanelSpec q, v;
      q.title = group + " samples";
      q.x = {"", false, {}};
      q.y = {kDeviatorKPaLabel, false, {}};
      q.legend = "best";
      v.x = {kAxialStrainLabel, false, {}};
      v.y = {kVolumetricStrainLabel, false, {}};
      v.legend = "none";
      for (std::size_t k = 0; k < members.size(); ++k) {
        const ElementCase& c = test(members[k]);
        const std::string label =
            fmt::format("$\\sigma'_3$ = {:g} kPa, $e_0$ = {}", sigma3(members[k]) / kKPa,
                        format_value(c.initial.e0));
        q.series.push_back(
            curve_series("triaxial.csv", members[k], "axial_strain_pct", "q_kPa", label, color(k)));
        v.series.push_back(curve_series("triaxial.csv", members[k], "axial_strain_pct",
                                        "volumetric_strain_pct", label, color(k)));
        labels.push_back(group);
      }
      q_panels.push_back(std::move(q));
      v_panels.push_back(std::move(v));
    }
    for (auto& p : q_panels) fig.panels.push_back(std::move(p));
    for (auto& p : v_panels) fig.panels.push_back(std::move(p));
    add_figure(item, std::move(fig));
    const PeakTable peaks = peak_table(names, labels);
    write_csv(item, "triaxial_peaks.csv", peaks.csv);
    std::string md =
        "Drained triaxial compression at constant cell pressure σ'_3 (also the isotropic "
        "consolidation stress) of the laboratory calibration series: dense, loose, and the two "
        "samples of the Deltares set at 200 kPa. Negative volumetric strain is dilation.\n\n";
    md += image("triaxial.png", "drained triaxial curves");
    md += markdown_table(peak_header(), peaks.rows, 2);
    return md;
  }

  // ---- Item 3: cyclic oedometer

  std::string cyclic_oedometer(StudyItem& item) {
    item.convention = convention_of(kCyclic);
    write_csv(item, "cyclic_oedometer.csv", curves_csv(kCyclic, kOedometerColumns, kCurveComment));
    // Stiffness of each, compared with the one without intergranular strain.
    const auto analyse = [this](const std::string& name) {
      const NumericTable& t = curve(name);
      std::vector<double> stress = t.column("sigma_a_kPa"), strain = t.column("axial_strain_pct");
      for (double& s : stress) s *= kKPa;
      for (double& e : strain) e /= 100.0;
      return analyse_cyclic_oedometer(stress, strain);
    };
    const CyclicOedometerStiffness reference = analyse(kCyclicReference);
    CsvText csv(
        "pilempm study calibration: cyclic oedometer stiffness; constrained moduli M = d "
        "sigma_v / d eps_v (secant); first loading from sigma_v0; reloading: the first "
        "reloading branch from its start to twice that; accumulated strain: vertical strain at "
        "the end minus at the end of the first loading (same stress); ratios to the test "
        "without intergranular strain",
        {"test",
         "igs",
         "m_R",
         "m_T",
         "R",
         "beta_r",
         "chi",
         "sigma_v0_kPa",
         "first_increment_to_kPa",
         "first_increment_modulus_MPa",
         "initial_secant_to_kPa",
         "initial_secant_modulus_MPa",
         "initial_secant_ratio_to_no_igs",
         "first_increment_ratio_to_no_igs",
         "reload_from_kPa",
         "reload_to_kPa",
         "reload_secant_modulus_MPa",
         "strain_after_first_loading_pct",
         "final_strain_pct",
         "accumulated_strain_pct",
         "cycles"});
    std::vector<std::vector<std::string>> rows;
    for (const std::string& name : kCyclic) {
      const ElementCase& c = test(name);
      CyclicStiffnessRow row;
      row.test = name;
      row.igs = c.igs ? c.igs->name : "none";
      row.stiffness = analyse(name);
      const CyclicOedometerStiffness& s = row.stiffness;
      row.initial_secant_ratio = s.initial_secant_modulus / reference.initial_secant_modulus;
      row.first_increment_ratio = s.first_increment_modulus / reference.first_increment_modulus;
      const IntergranularStrainParameters g =
          c.igs ? c.igs->parameters : IntergranularStrainParameters{};
      const auto igs_value = [&g](double v) { return g.enabled() ? csv_number(v) : std::string(); };
      csv.add({name,
               row.igs,
               igs_value(g.m_R),
               igs_value(g.m_T),
               igs_value(g.R),
               igs_value(g.beta_r),
               igs_value(g.chi),
               csv_number(s.initial_stress / kKPa),
               csv_number(s.first_increment_stress / kKPa),
               csv_number(s.first_increment_modulus / kMPa),
               csv_number(2.0 * s.initial_stress / kKPa),
               csv_number(s.initial_secant_modulus / kMPa),
               csv_number(row.initial_secant_ratio),
               csv_number(row.first_increment_ratio),
               csv_number(s.reload_from / kKPa),
               csv_number(s.reload_to / kKPa),
               csv_number(s.reload_secant_modulus / kMPa),
               csv_number(100.0 * s.strain_after_first_loading),
               csv_number(100.0 * s.final_strain),
               csv_number(100.0 * s.accumulated_strain),
               std::to_string(s.unload_reload_cycles)});
      rows.push_back(
          {row.igs,
           g.enabled()
               ? fmt::format("{:g}, {:g}, {:g}, {:g}, {:g}", g.m_R, g.m_T, g.R, g.beta_r, g.chi)
               : "–",
           fixed(s.initial_secant_modulus / kMPa, 2), fixed(row.initial_secant_ratio, 3),
           fixed(s.first_increment_modulus / kMPa, 2), fixed(row.first_increment_ratio, 3),
           fixed(s.reload_secant_modulus / kMPa, 1), fixed(100.0 * s.strain_after_first_loading, 4),
           fixed(100.0 * s.accumulated_strain, 4)});
      report_.cyclic_stiffness.push_back(row);
    }
    write_csv(item, "cyclic_oedometer_stiffness.csv", csv.text());

    const CyclicOedometerStiffness& s0 = reference;
    // Zoom of the second panel: the first loading up to five times the initial stress.
    const double zoom_stress = 5.0 * s0.initial_stress;
    double zoom_strain = 0.0;
    for (const std::string& name : kCyclic) {
      const NumericTable& t = curve(name);
      const auto& stress = t.column("sigma_a_kPa");
      const auto& strain = t.column("axial_strain_pct");
      for (std::size_t i = 0; i < stress.size(); ++i)
        if (stress[i] * kKPa >= zoom_stress) {
          zoom_strain = std::max(zoom_strain, strain[i]);
          break;
        }
    }
    FigureSpec fig;
    fig.file = "cyclic_oedometer.png";
    fig.title = "Cyclic oedometer, original set: intergranular strain sets and the basic model";
    fig.cols = 2;
    fig.width_in = 13.0;
    fig.height_in = 5.2;
    PanelSpec whole, zoom;
    const OedometerTest& programme = std::get<OedometerTest>(test(kCyclic[0]).test);
    std::string targets;
    for (double t : programme.sigma_v_targets) targets += fmt::format(" → {:g}", t / kKPa);
    whole.title = fmt::format("{:g}{} kPa", programme.sigma_v0 / kKPa, targets);
    whole.x = {"vertical strain $\\varepsilon_v$ [%]", false, {}};
    whole.y = {"vertical effective stress $\\sigma'_v$ [kPa]", false, {}};
    whole.legend = "upper left";
    zoom.title =
        fmt::format("start of the first loading ($\\sigma'_v$ ≤ {:g} kPa): initial stiffness",
                    zoom_stress / kKPa);
    zoom.x = {"vertical strain $\\varepsilon_v$ [%]", false, std::pair{0.0, 1.05 * zoom_strain}};
    zoom.y = {"vertical effective stress $\\sigma'_v$ [kPa]", false,
              std::pair{0.0, 1.02 * zoom_stress / kKPa}};
    zoom.legend = "lower right";
    for (std::size_t k = 0; k < kCyclic.size(); ++k) {
      const ElementCase& c = test(kCyclic[k]);
      const bool none = !(c.igs && c.igs->parameters.enabled());
      const std::string label = none ? "no IGS (basic model)" : c.igs->name;
      const std::string style = none ? "--" : "-";
      const std::string colour = none ? "black" : color(k);
      whole.series.push_back(curve_series("cyclic_oedometer.csv", kCyclic[k], "vertical_strain_pct",
                                          "sigma_v_kPa", label, colour, style, 1.4));
      zoom.series.push_back(curve_series("cyclic_oedometer.csv", kCyclic[k], "vertical_strain_pct",
                                         "sigma_v_kPa", label, colour, style, 1.6));
    }
    fig.panels = {std::move(whole), std::move(zoom)};
    add_figure(item, std::move(fig));

    std::string md = fmt::format(
        "Oedometer cycles {:g}{} kPa (K0 = {:g}), original set, with each intergranular "
        "strain set (IGS, Niemunis & Herle 1997) and without. The initial stiffness is the "
        "secant constrained modulus M = Δσ'_v/Δε_v of the first loading from σ'_v0 = {:g} to "
        "{:g} kPa; the first-increment modulus is the secant over the first increment only "
        "({:g} → {:.3g} kPa, so it depends on the step size). The study expects the initial "
        "stiffness with IGS to be close to the one without: with the sample's intergranular "
        "strain fully mobilised by its isotropic compression (ρ = 1), the oedometric loading "
        "direction is partly new to it, so the IGS stiffens only the first strains of the order "
        "of R (IGS 1–3 differ only in β_r and χ, which matter little while ρ stays near 1, so "
        "their first loadings coincide). The reloading modulus is the secant of the first "
        "reloading from {:g} to {:g} kPa "
        "(where the IGS matters); the accumulated strain is the vertical strain the cycles "
        "added at {:g} kPa.\n\n",
        programme.sigma_v0 / kKPa, targets, programme.K0, s0.initial_stress / kKPa,
        2.0 * s0.initial_stress / kKPa, s0.initial_stress / kKPa, s0.first_increment_stress / kKPa,
        s0.reload_from / kKPa, s0.reload_to / kKPa, programme.sigma_v_targets.front() / kKPa);
    md += image("cyclic_oedometer.png", "cyclic oedometer curves");
    md += markdown_table({"IGS", "m_R, m_T, R, β_r, χ", "initial M [MPa]", "ratio to no IGS",
                          "first-increment M [MPa]", "ratio to no IGS", "reloading M [MPa]",
                          "ε_v after first loading [%]", "ε_v accumulated by the cycles [%]"},
                         rows, 2);
    return md;
  }

  // ---- Item 4: high-pressure triaxial and Bolton

  std::string high_pressure(StudyItem& item) {
    item.convention = convention_of(kHighPressure);
    write_csv(item, "high_pressure_triaxial.csv",
              curves_csv(kHighPressure, kTriaxialColumns, kTriaxialComment));
    CsvText csv(
        fmt::format("pilempm study calibration: high-pressure drained triaxial, peak of q, beside "
                    "Bolton (1986) at I_D = {:g}, phi_c = {:g} deg and p' = sigma3 (the study's "
                    "table); psi after Schanz & Vermeer",
                    kBoltonRelativeDensity, kBoltonPhiC),
        {"test", "sigma3_kPa", "sigma3_MPa", "e0", "e0_at", "initial_void_ratio", "peak_q_kPa",
         "axial_strain_at_peak_pct", "phi_peak_deg", "psi_peak_deg", "peak_at_end", "bolton_I_D",
         "bolton_phi_c_deg", "bolton_p_kPa", "bolton_I_R", "bolton_phi_max_deg",
         "bolton_dilatancy_rate", "bolton_psi_max_deg"});
    std::vector<std::vector<std::string>> rows;
    for (const std::string& name : kHighPressure) {
      const ElementRunRecord& r = record(name);
      HighPressureRow row;
      row.test = name;
      row.sigma3 = sigma3(name);
      row.initial_void_ratio = r.summary.initial_void_ratio;
      row.peak_q = r.summary.peak_q;
      row.axial_strain_at_peak = r.summary.axial_strain_at_peak;
      row.phi_peak_deg = r.summary.phi_at_peak_deg;
      row.psi_peak_deg = r.summary.psi_at_peak_deg;
      row.peak_at_end = r.summary.peak_at_end;
      row.bolton = bolton(kBoltonRelativeDensity, kBoltonPhiC, row.sigma3);
      csv.add({name, csv_number(row.sigma3 / kKPa), csv_number(row.sigma3 / kMPa),
               format_value(r.test->initial.e0), convention_name(r.test->initial.e0_at),
               csv_number(row.initial_void_ratio), csv_number(row.peak_q / kKPa),
               csv_number(100.0 * row.axial_strain_at_peak), csv_number(row.phi_peak_deg),
               csv_number(row.psi_peak_deg), row.peak_at_end ? "true" : "false",
               csv_number(kBoltonRelativeDensity), csv_number(kBoltonPhiC),
               csv_number(row.sigma3 / kKPa), csv_number(row.bolton.relative_dilatancy_index),
               csv_number(row.bolton.phi_max_deg), csv_number(row.bolton.dilatancy_rate),
               csv_number(row.bolton.psi_max_deg)});
      rows.push_back({fmt::format("{:g}", row.sigma3 / kMPa), fixed(row.initial_void_ratio, 4),
                      fmt::format("{:.4g}{}", row.peak_q / kMPa, row.peak_at_end ? " (end)" : ""),
                      fixed(100.0 * row.axial_strain_at_peak, 2), fixed(row.phi_peak_deg, 2),
                      fixed(row.psi_peak_deg, 2), fixed(row.bolton.relative_dilatancy_index, 3),
                      fixed(row.bolton.phi_max_deg, 3), fixed(row.bolton.psi_max_deg, 3)});
      report_.high_pressure.push_back(row);
    }
    write_csv(item, "high_pressure_table.csv", csv.text());

    FigureSpec curves;
    curves.file = "high_pressure_triaxial.png";
    curves.title = fmt::format(
        "High-pressure drained triaxial, set {}, $e_0$ = {} at p = 0 (R_D = 95 %)",
        test(kHighPressure[0]).material.name, format_value(test(kHighPressure[0]).initial.e0));
    curves.cols = 2;
    curves.width_in = 13.0;
    curves.height_in = 5.6;
    curves.shared_legend = true;
    curves.legend_columns = static_cast<int>(kHighPressure.size());
    PanelSpec phi, v;
    phi.x = v.x = {kAxialStrainLabel, false, {}};
    phi.y = {"mobilised friction angle $\\varphi_{mob}$ [°]", false, {}};
    v.y = {kVolumetricStrainLabel, false, {}};
    for (std::size_t k = 0; k < kHighPressure.size(); ++k) {
      const std::string label =
          fmt::format("$\\sigma'_3$ = {:g} MPa", sigma3(kHighPressure[k]) / kMPa);
      phi.series.push_back(curve_series("high_pressure_triaxial.csv", kHighPressure[k],
                                        "axial_strain_pct", "phi_mob_deg", label, color(k)));
      v.series.push_back(curve_series("high_pressure_triaxial.csv", kHighPressure[k],
                                      "axial_strain_pct", "volumetric_strain_pct", label,
                                      color(k)));
    }
    curves.panels = {std::move(phi), std::move(v)};
    add_figure(item, std::move(curves));

    FigureSpec peaks;
    peaks.file = "high_pressure_peaks.png";
    peaks.title = "Peak friction and dilatancy angles against cell pressure: model and Bolton";
    peaks.cols = 2;
    peaks.width_in = 12.0;
    peaks.height_in = 5.0;
    const auto table_series = [](const std::string& y, const std::string& label,
                                 const std::string& colour, const std::string& style,
                                 const std::string& marker) {
      SeriesSpec s;
      s.csv = "high_pressure_table.csv";
      s.x = "sigma3_MPa";
      s.y = y;
      s.label = label;
      s.style.color = colour;
      s.style.linestyle = style;
      s.style.marker = marker;
      s.style.markersize = marker.empty() ? 0.0 : 6.0;
      return s;
    };
    PanelSpec pphi, ppsi;
    pphi.title = "peak friction angle";
    ppsi.title = "dilatancy angle at the peak";
    pphi.x = ppsi.x = {"cell pressure $\\sigma'_3$ [MPa] (log scale)", true, {}};
    pphi.y = {"friction angle $\\varphi$ [°]", false, {}};
    ppsi.y = {"dilatancy angle $\\psi$ [°] (negative: contraction)", false, {}};
    pphi.series = {table_series("phi_peak_deg", "hypoplastic model, peak", "C0", "-", "o"),
                   table_series("bolton_phi_max_deg",
                                fmt::format("Bolton (1986), $I_D$ = {:g}, $p'$ = $\\sigma'_3$",
                                            kBoltonRelativeDensity),
                                "C3", "--", "s"),
                   table_series("bolton_phi_c_deg",
                                fmt::format("$\\varphi_c$ = {:g}°", kBoltonPhiC), "grey", ":", "")};
    ppsi.series = {table_series("psi_peak_deg", "hypoplastic model, at the peak", "C0", "-", "o"),
                   table_series("bolton_psi_max_deg",
                                fmt::format("Bolton (1986), $I_D$ = {:g}, $p'$ = $\\sigma'_3$",
                                            kBoltonRelativeDensity),
                                "C3", "--", "s")};
    pphi.legend = ppsi.legend = "lower left";
    peaks.panels = {std::move(pphi), std::move(ppsi)};
    add_figure(item, std::move(peaks));

    std::string md = fmt::format(
        "Drained triaxial compression of the dense sand (e0 = {} at zero pressure, R_D = 95 %) "
        "at cell pressures up to 30 MPa with the {} set. φ is the mobilised friction angle at "
        "the peak of q (sin φ = (σ1 − σ3)/(σ1 + σ3)), ψ the dilatancy angle from dε_v/dε_1 at "
        "the peak (sin ψ = −(dε_v/dε_1)/(2 − dε_v/dε_1), Schanz & Vermeer). Bolton (1986) with "
        "I_D = {:g}, φc = {:g}° at p' = σ'_3 (as the study's table): I_R = I_D (10 − ln p') − 1, "
        "φ_max = φc + 3 I_R, sin ψ_max = 0.3 I_R/(2 + 0.3 I_R). Bolton's peak falls below φc "
        "(contraction, ψ < 0) at the highest pressures, where the model still dilates at its "
        "peak.\n\n",
        format_value(test(kHighPressure[0]).initial.e0), test(kHighPressure[0]).material.name,
        kBoltonRelativeDensity, kBoltonPhiC);
    md += image("high_pressure_peaks.png", "peak angles against pressure");
    md += markdown_table({"σ3 [MPa]", "e at start", "peak q [MPa]", "ε1 at peak [%]", "φ peak [°]",
                          "ψ peak [°]", "Bolton I_R", "Bolton φ_max [°]", "Bolton ψ_max [°]"},
                         rows, 0);
    md += image("high_pressure_triaxial.png", "high-pressure triaxial curves");
    return md;
  }

  // ---- Item 5: alpha against p

  std::string alpha_pressure(StudyItem& item) {
    const HypoplasticParameters original = hypoplastic_set("original");
    const StressDependence law{};  // the option's defaults
    const std::vector<VoidRatioConvention> conventions = {VoidRatioConvention::at_initial_stress,
                                                          VoidRatioConvention::at_zero_pressure};
    item.convention =
        "both, as two families of curves: `initial-stress`, e = e0 at every p (solid; the "
        "void ratio of the state considered, the recipe that gives α ≈ 0.13 at 100 kPa for e = "
        "0.68), and `zero-pressure`, e0 at p = 0 compressed along Bauer's law e = e0 "
        "exp[−(3p/h_s)^n] (dashed; I_D then stays constant)";
    // The curve: 10 kPa to 30 MPa, geometric.
    constexpr int kPoints = 71;
    std::vector<double> grid;
    for (int k = 0; k < kPoints; ++k)
      grid.push_back(10.0 * kKPa * std::pow(3000.0, static_cast<double>(k) / (kPoints - 1)));
    CsvText csv(
        "pilempm study calibration: Herle & Gudehus (1999) alpha against p in isotropic "
        "compression, original set; e_d, e_c from Bauer's law at p; I_D = (e_c - e)/(e_c - "
        "e_d); phi_p from Bolton (1986) with that I_D at p; alpha empty where undefined "
        "(status)",
        {"series", "e0", "e0_convention", "p_kPa", "void_ratio", "e_d", "e_c", "I_D", "phi_p_deg",
         "alpha", "status"});
    const auto series_name = [](double e0, VoidRatioConvention c) {
      return fmt::format("e0={} {}", format_value(e0), convention_name(c));
    };
    for (VoidRatioConvention c : conventions)
      for (double e0 : kAlphaVoidRatios) {
        AlphaPressureSeries series{e0, c, alpha_curve(original, e0, c, grid)};
        for (const AlphaPoint& a : series.points)
          csv.add({series_name(e0, c), format_value(e0), convention_name(c),
                   csv_number(a.mean_stress / kKPa), csv_number(a.void_ratio), csv_number(a.e_d),
                   csv_number(a.e_c), csv_number(a.relative_density),
                   a.phi_p_deg ? csv_number(*a.phi_p_deg) : "", a.alpha ? csv_number(*a.alpha) : "",
                   std::string(to_string(a.status))});
      }
    write_csv(item, "alpha_pressure.csv", csv.text());
    CsvText law_csv(
        fmt::format(
            "pilempm study calibration: alpha of the stress-dependent option with its defaults "
            "(alpha_low = {:g} up to p_low = {:g} kPa, alpha_high = {:g} from p_high = {:g} kPa, "
            "smoothstep in ln p), and the constant alpha of the original and modified sets",
            law.alpha_low, law.p_low / kKPa, law.alpha_high, law.p_high / kKPa),
        {"p_kPa", "alpha_stress_dependent_option", "alpha_original_set", "alpha_modified_set"});
    const double alpha_modified = hypoplastic_set("modified-medium-dense").alpha;
    for (double p : grid)
      law_csv.add({csv_number(p / kKPa), csv_number(law.alpha(p)), csv_number(original.alpha),
                   csv_number(alpha_modified)});
    write_csv(item, "alpha_pressure_law.csv", law_csv.text());

    // The table at round pressures (the structured result of the report too).
    std::vector<double> table_pressures;
    for (double p : kAlphaTablePressuresKPa) table_pressures.push_back(p * kKPa);
    std::vector<std::string> header = {"p [kPa]"};
    std::vector<std::vector<std::string>> rows(table_pressures.size());
    for (std::size_t i = 0; i < table_pressures.size(); ++i)
      rows[i].push_back(fmt::format("{:g}", table_pressures[i] / kKPa));
    for (VoidRatioConvention c : conventions)
      for (double e0 : kAlphaVoidRatios) {
        AlphaPressureSeries series{e0, c, alpha_curve(original, e0, c, table_pressures)};
        header.push_back(c == VoidRatioConvention::at_initial_stress
                             ? fmt::format("α, e = {} at every p", format_value(e0))
                             : fmt::format("α, e0 = {} at p = 0", format_value(e0)));
        for (std::size_t i = 0; i < series.points.size(); ++i) {
          const AlphaPoint& a = series.points[i];
          rows[i].push_back(a.alpha ? fixed(*a.alpha, 4)
                                    : (a.status == AlphaStatus::no_peak
                                           ? std::string("no peak")
                                           : std::string(to_string(a.status))));
        }
        report_.alpha_pressure.push_back(std::move(series));
      }
    header.push_back("α of the option");
    for (std::size_t i = 0; i < table_pressures.size(); ++i)
      rows[i].push_back(fixed(law.alpha(table_pressures[i]), 4));

    FigureSpec fig;
    fig.file = "alpha_pressure.png";
    fig.title = "Exponent α against mean pressure: Herle & Gudehus with Bolton, original set";
    fig.width_in = 10.0;
    fig.height_in = 6.0;
    PanelSpec panel;
    panel.x = {"mean effective stress $p'$ [kPa] (log scale)", true, {}};
    panel.y = {"exponent α [-]", false, {}};
    panel.legend = "upper right";
    for (VoidRatioConvention c : conventions)
      for (std::size_t k = 0; k < kAlphaVoidRatios.size(); ++k) {
        const double e0 = kAlphaVoidRatios[k];
        SeriesSpec s;
        s.csv = "alpha_pressure.csv";
        s.where = {{"series", series_name(e0, c)}};
        s.x = "p_kPa";
        s.y = "alpha";
        s.label =
            c == VoidRatioConvention::at_initial_stress
                ? fmt::format("Herle & Gudehus, e = {} at every p", format_value(e0))
                : fmt::format("Herle & Gudehus, $e_0$ = {} at p = 0 (Bauer)", format_value(e0));
        s.style.color = color(k);
        s.style.linestyle = c == VoidRatioConvention::at_initial_stress ? "-" : "--";
        s.style.linewidth = 1.8;
        panel.series.push_back(std::move(s));
      }
    const auto law_series = [](const std::string& y, const std::string& label,
                               const std::string& colour, const std::string& style, double width) {
      SeriesSpec s;
      s.csv = "alpha_pressure_law.csv";
      s.x = "p_kPa";
      s.y = y;
      s.label = label;
      s.style.color = colour;
      s.style.linestyle = style;
      s.style.linewidth = width;
      return s;
    };
    panel.series.push_back(
        law_series("alpha_stress_dependent_option",
                   fmt::format("stress-dependent α option (defaults: {:g} → {:g})", law.alpha_low,
                               law.alpha_high),
                   "black", "-", 2.6));
    panel.series.push_back(law_series("alpha_original_set",
                                      fmt::format("original set, α = {:g}", original.alpha), "grey",
                                      ":", 1.4));
    panel.series.push_back(law_series("alpha_modified_set",
                                      fmt::format("modified set, α = {:g}", alpha_modified), "grey",
                                      "-.", 1.4));
    fig.panels.push_back(std::move(panel));
    add_figure(item, std::move(fig));

    std::string md = fmt::format(
        "α from a peak state (Herle & Gudehus 1999) for isotropic compression with the "
        "original set: at each p, e_d and e_c from Bauer's law, I_D = (e_c − e)/(e_c − e_d), "
        "the peak angle φ_p from Bolton (1986) with that I_D at p' = p, and α = ln f_d / "
        "ln[(e − e_d)/(e_c − e_d)]. Where φ_p ≤ φc there is no peak and so no α (\"no peak\"): "
        "α falls with pressure and ends. The stress-dependent α option of the model (its "
        "defaults: α = {:g} up to {:g} MPa, {:g} from {:g} MPa, a smoothstep in ln p between) is "
        "drawn with it. It falls like the Herle & Gudehus α but at pressures about three to five "
        "times higher: its defaults were calibrated on the triaxial peaks of item 8 (original "
        "set at 0.1 MPa, modified set at 10 MPa), not on this curve, and it stays above zero, "
        "so the model keeps a small peak where this recipe finds none.\n\n",
        law.alpha_low, law.p_low / kMPa, law.alpha_high, law.p_high / kMPa);
    md += image("alpha_pressure.png", "alpha against pressure");
    md += markdown_table(header, rows, 0);
    return md;
  }

  // ---- Item 6: alpha sensitivity at 6 MPa

  std::string alpha_sensitivity(StudyItem& item) {
    item.convention = convention_of(kAlphaSensitivity);
    write_csv(item, "alpha_sensitivity.csv",
              curves_csv(kAlphaSensitivity, kTriaxialColumns, kTriaxialComment));
    FigureSpec fig;
    fig.file = "alpha_sensitivity.png";
    fig.title = fmt::format(
        "Drained triaxial at $\\sigma'_3$ = {:g} MPa, $e_0$ = {} at p = 0 (R_D = 95 %): "
        "sensitivity to α",
        sigma3(kAlphaSensitivity[0]) / kMPa, format_value(test(kAlphaSensitivity[0]).initial.e0));
    fig.cols = 2;
    fig.width_in = 13.0;
    fig.height_in = 5.2;
    PanelSpec q, v;
    q.x = v.x = {kAxialStrainLabel, false, {}};
    q.y = {kDeviatorMPaLabel, false, {}};
    v.y = {kVolumetricStrainLabel, false, {}};
    q.legend = "lower right";
    v.legend = "lower left";
    std::vector<std::string> labels;
    for (std::size_t k = 0; k < kAlphaSensitivity.size(); ++k) {
      const ElementCase& c = test(kAlphaSensitivity[k]);
      const std::string label = fmt::format("α = {:g}", c.material.hypoplastic().alpha);
      labels.push_back(label);
      q.series.push_back(curve_series("alpha_sensitivity.csv", c.name, "axial_strain_pct", "q_MPa",
                                      label, color(k)));
      v.series.push_back(curve_series("alpha_sensitivity.csv", c.name, "axial_strain_pct",
                                      "volumetric_strain_pct", label, color(k)));
    }
    fig.panels = {std::move(q), std::move(v)};
    add_figure(item, std::move(fig));
    const PeakTable peaks = peak_table(kAlphaSensitivity, labels);
    write_csv(item, "alpha_sensitivity_peaks.csv", peaks.csv);
    std::string md =
        "The original set with α changed alone (α = 0.12 is the original set itself, the 6 MPa "
        "test of the high-pressure series). α scales the pyknotropy factor f_d: a smaller α "
        "gives less peak strength and less dilation at the same density.\n\n";
    md += image("alpha_sensitivity.png", "alpha sensitivity");
    md += markdown_table(peak_header(), peaks.rows, 2);
    return md;
  }

  // ---- Items 7 and 8: the sets at 0.1 and 10 MPa

  // A 2x2 figure: columns low and high pressure, rows q and volumetric strain.
  FigureSpec pressure_pair_figure(const std::string& file, const std::string& csv,
                                  const std::string& title,
                                  const std::vector<std::pair<std::string, std::string>>& pairs,
                                  const std::vector<std::string>& labels,
                                  const std::vector<std::string>& colours,
                                  const std::vector<std::string>& styles) {
    FigureSpec fig;
    fig.file = file;
    fig.title = title;
    fig.rows = 2;
    fig.cols = 2;
    fig.width_in = 13.0;
    fig.height_in = 9.0;
    fig.sharex = true;
    fig.shared_legend = true;
    PanelSpec q_low, q_high, v_low, v_high;
    q_low.title = fmt::format("$\\sigma'_3$ = {:g} MPa", sigma3(pairs[0].first) / kMPa);
    q_high.title = fmt::format("$\\sigma'_3$ = {:g} MPa", sigma3(pairs[0].second) / kMPa);
    q_low.y = {kDeviatorKPaLabel, false, {}};
    q_high.y = {kDeviatorMPaLabel, false, {}};
    v_low.x = v_high.x = {kAxialStrainLabel, false, {}};
    v_low.y = v_high.y = {kVolumetricStrainLabel, false, {}};
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const double width = k == 0 && pairs.size() == 3 ? 2.4 : 1.6;
      q_low.series.push_back(curve_series(csv, pairs[k].first, "axial_strain_pct", "q_kPa",
                                          labels[k], colours[k], styles[k], width));
      q_high.series.push_back(curve_series(csv, pairs[k].second, "axial_strain_pct", "q_MPa",
                                           labels[k], colours[k], styles[k], width));
      v_low.series.push_back(curve_series(csv, pairs[k].first, "axial_strain_pct",
                                          "volumetric_strain_pct", labels[k], colours[k], styles[k],
                                          width));
      v_high.series.push_back(curve_series(csv, pairs[k].second, "axial_strain_pct",
                                           "volumetric_strain_pct", labels[k], colours[k],
                                           styles[k], width));
    }
    fig.panels = {std::move(q_low), std::move(q_high), std::move(v_low), std::move(v_high)};
    return fig;
  }

  std::string set_label(const std::string& name) const {
    const MaterialSpec& m = test(name).material;
    const StressDependence& d = m.hypoplastic().stress_dependence;
    if (d.alpha_varies)
      return fmt::format(
          "{} with stress-dependent α ({:g} → {:g})",
          m.hypoplastic_material().base.empty() ? m.name : m.hypoplastic_material().base,
          d.alpha_low, d.alpha_high);
    return fmt::format("{} set (φc = {:g}°, α = {:g})", m.name, m.hypoplastic().phi_c_deg,
                       m.hypoplastic().alpha);
  }

  std::string modified_vs_original(StudyItem& item) {
    const std::vector<std::string> names = {kOriginal.first, kModified.first, kOriginal.second,
                                            kModified.second};
    item.convention = convention_of(names);
    write_csv(item, "modified_vs_original.csv",
              curves_csv(names, kTriaxialColumns, kTriaxialComment));
    const std::vector<std::string> labels = {set_label(kOriginal.first),
                                             set_label(kModified.first)};
    add_figure(
        item, pressure_pair_figure("modified_vs_original.png", "modified_vs_original.csv",
                                   fmt::format("Original against modified set, $e_0$ = {} at p = 0",
                                               format_value(test(kOriginal.first).initial.e0)),
                                   {kOriginal, kModified}, labels, {"C0", "C1"}, {"-", "--"}));
    const PeakTable peaks =
        peak_table(names, {set_label(kOriginal.first), set_label(kModified.first),
                           set_label(kOriginal.second), set_label(kModified.second)});
    write_csv(item, "modified_vs_original_peaks.csv", peaks.csv);
    const HypoplasticParameters& m = test(kModified.first).material.hypoplastic();
    std::string md = fmt::format(
        "The modified medium-dense set (φc = {:g}°, e_d0/e_c0/e_i0 = {:g}/{:g}/{:g} after Rohe "
        "at 10 MPa, α = {:g}) against the original set, at σ'_3 = 10 MPa (the stress level "
        "below the pile tip) and 0.1 MPa. The modified set removes most of the peak and the "
        "dilation at both pressures.\n\n",
        m.phi_c_deg, m.e_d0, m.e_c0, m.e_i0, m.alpha);
    md += image("modified_vs_original.png", "modified against original set");
    md += markdown_table(peak_header(), peaks.rows, 2);
    return md;
  }

  std::string stress_dependent_alpha(StudyItem& item) {
    const std::vector<std::string> names = {kStressDependent.first, kOriginal.first,
                                            kModified.first,        kStressDependent.second,
                                            kOriginal.second,       kModified.second};
    item.convention = convention_of(names);
    write_csv(item, "stress_dependent_alpha.csv",
              curves_csv(names, kTriaxialColumns, kTriaxialComment));
    const std::vector<std::string> labels = {
        set_label(kStressDependent.first), set_label(kOriginal.first), set_label(kModified.first)};
    add_figure(item, pressure_pair_figure(
                         "stress_dependent_alpha.png", "stress_dependent_alpha.csv",
                         fmt::format("Stress-dependent α option against the original and the "
                                     "modified set, $e_0$ = {} at p = 0",
                                     format_value(test(kOriginal.first).initial.e0)),
                         {kStressDependent, kOriginal, kModified}, labels, {"black", "C0", "C1"},
                         {"-", "--", ":"}));

    CsvText csv(
        "pilempm study calibration: peak friction angle of the stress-dependent alpha option "
        "against the original set at low pressure and the modified set at high pressure "
        "(drained triaxial); within_1_deg: |difference| <= 1 deg",
        {"sigma3_kPa", "initial_void_ratio", "alpha_option_at_start", "phi_peak_option_deg",
         "phi_peak_original_deg", "phi_peak_modified_deg", "compared_with", "difference_deg",
         "within_1_deg"});
    std::vector<std::vector<std::string>> rows;
    const auto add_row = [&](const std::string& option, const std::string& original,
                             const std::string& modified, bool against_original) {
      StressDependentRow row;
      row.sigma3 = sigma3(option);
      row.initial_void_ratio = record(option).summary.initial_void_ratio;
      row.alpha_at_start = test(option).material.hypoplastic().stress_dependence.alpha(row.sigma3);
      row.phi_option_deg = record(option).summary.phi_at_peak_deg;
      row.phi_original_deg = record(original).summary.phi_at_peak_deg;
      row.phi_modified_deg = record(modified).summary.phi_at_peak_deg;
      row.compared_with = against_original ? "original" : "modified";
      row.difference_deg =
          row.phi_option_deg - (against_original ? row.phi_original_deg : row.phi_modified_deg);
      const bool within = std::abs(row.difference_deg) <= kStressDependentTolerance;
      csv.add({csv_number(row.sigma3 / kKPa), csv_number(row.initial_void_ratio),
               csv_number(row.alpha_at_start), csv_number(row.phi_option_deg),
               csv_number(row.phi_original_deg), csv_number(row.phi_modified_deg),
               row.compared_with, csv_number(row.difference_deg), within ? "true" : "false"});
      rows.push_back({fmt::format("{:g}", row.sigma3 / kMPa), fixed(row.initial_void_ratio, 4),
                      fixed(row.alpha_at_start, 4), fixed(row.phi_option_deg, 2),
                      fixed(row.phi_original_deg, 2), fixed(row.phi_modified_deg, 2),
                      row.compared_with, fmt::format("{:+.2f}", row.difference_deg),
                      within ? "yes" : "NO"});
      report_.stress_dependent.push_back(row);
    };
    add_row(kStressDependent.first, kOriginal.first, kModified.first, true);
    add_row(kStressDependent.second, kOriginal.second, kModified.second, false);
    write_csv(item, "stress_dependent_alpha_table.csv", csv.text());
    const PeakTable peaks =
        peak_table(names, {labels[0], labels[1], labels[2], labels[0], labels[1], labels[2]});
    write_csv(item, "stress_dependent_alpha_peaks.csv", peaks.csv);

    const StressDependence& d =
        test(kStressDependent.first).material.hypoplastic().stress_dependence;
    std::string md = fmt::format(
        "Beyond the study (BRIEF §6): the study concludes that α should fall as the stress "
        "level rises. The model option `stress_dependence = {{ alpha = true }}` on the original "
        "set lets α follow p: {:g} up to {:g} MPa, {:g} from {:g} MPa on, a smoothstep in ln p "
        "between (α and its slope continuous; item 5 draws the law beside the Herle & Gudehus "
        "α). It should behave like the original set at 0.1 MPa and like the modified set at "
        "10 MPa: peak friction angles within {:g}° (also checked by the library's test "
        "tests/element/test_stress_dependent_alpha_peaks.cpp, in both conventions).\n\n",
        d.alpha_low, d.p_low / kMPa, d.alpha_high, d.p_high / kMPa, kStressDependentTolerance);
    md += markdown_table({"σ3 [MPa]", "e at start", "α of the option at p0", "φ peak option [°]",
                          "φ peak original [°]", "φ peak modified [°]", "compared with",
                          "difference [°]", "within 1°"},
                         rows, 0);
    md += image("stress_dependent_alpha.png", "stress-dependent alpha option");
    md += markdown_table(peak_header(), peaks.rows, 2);
    return md;
  }

  // ---- Plots and README

  void draw() {
    // Old figures never stay beside new data: remove them first.
    for (const FigureSpec& f : figures_) {
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

  // Run in the output folder (the script finds the CSV files next to figures.json).
  static std::string plot_command() { return "/usr/bin/python3 plot_figures.py figures.json"; }

  std::string readme() const {
    std::string md = "# Calibration study: hypoplastic model, Baskarp sand\n\n";
    md += fmt::format(
        "Written by `pilempm study calibration{}` (pilempm 0.1.0). It reproduces the "
        "element-test and analytical chapters of the Deltares study (BRIEF.md §3–§4: oedometer, "
        "cyclic oedometer, drained triaxial, high-pressure triaxial beside Bolton, α after Herle "
        "& Gudehus, sensitivity to α, modified against original set) and adds the "
        "stress-dependent α option (§6). Stresses and strains are compression positive; strains "
        "are logarithmic (sums of the increments), in percent. Each item has a CSV with the unit "
        "in every column name and a figure; the element tests behind them are in `tests/`.\n\n",
        report_.quick ? " --quick" : "");
    if (report_.quick)
      md +=
          "**Quick run** (`--quick`): every test ran with a quarter of the increments of "
          "`tests/case.toml`, for the test suite. The curves are coarser; run without `--quick` "
          "for the study's figures.\n\n";
    if (!report_.plots.plotted)
      md += fmt::format(
          "**The figures were not drawn**: {}.{} The CSV files and `figures.json` are complete; "
          "to draw the PNG files later, in this folder (Debian: `apt-get install "
          "python3-matplotlib`):\n\n"
          "```sh\n{}\n```\n\n",
          report_.plots.problem,
          report_.plots.tried.empty()
              ? std::string()
              : fmt::format(" Tried: {}.", fmt::join(report_.plots.tried, "; ")),
          plot_command());
    if (report_.tests_failed > 0 || failed_items() > 0)
      md += fmt::format(
          "**{} of {} element tests failed; {} items are incomplete** (see "
          "below and `tests/summary.md`).\n\n",
          report_.tests_failed, report_.tests_run, failed_items());

    md += "## Items and their initial void-ratio convention\n\n";
    md +=
        "Every element test states how its initial void ratio e0 is meant (BRIEF §2): "
        "`initial-stress` (e0 is the void ratio at the initial stress) or `zero-pressure` (e0 "
        "is a reference at p = 0, scaled to the initial mean stress by Bauer's law). The void "
        "ratio actually used at the start is in every table and CSV (`initial_void_ratio`).\n\n";
    std::vector<std::vector<std::string>> rows;
    for (std::size_t i = 0; i < report_.items.size(); ++i) {
      const StudyItem& item = report_.items[i];
      std::vector<std::string> files = item.csv;
      files.insert(files.end(), item.png.begin(), item.png.end());
      std::string links;
      for (const std::string& f : files)
        links += (links.empty() ? "" : ", ") + fmt::format("[{0}]({0})", f);
      rows.push_back({fmt::format("{}. [{}](#{})", i + 1, item.title, anchor(i)),
                      item.ok ? item.convention : "FAILED", links});
    }
    md += markdown_table({"item", "initial void ratio convention", "files"}, rows, 3);

    for (std::size_t i = 0; i < report_.items.size(); ++i) {
      const StudyItem& item = report_.items[i];
      md += fmt::format("<a id=\"{}\"></a>\n## {}. {}\n\n", anchor(i), i + 1, item.title);
      if (!item.ok) {
        md += fmt::format("**FAILED**: {}\n\n", item.error);
        continue;
      }
      md += fmt::format("*Initial void ratio*: {}.\n\n", item.convention);
      md += item_bodies_[i];
      std::string links;
      for (const std::string& f : item.csv)
        links += (links.empty() ? "" : ", ") + fmt::format("[{0}]({0})", f);
      md += fmt::format("Data: {}.\n\n", links);
    }

    md += "## Files\n\n";
    md += fmt::format(
        "- `README.md`: this summary; `figures.json`: every figure (file, title, axes with "
        "units, log axes, series: CSV file, columns, rows, label, style); `plot_figures.py`: "
        "the script that draws them.\n"
        "- `tests/`: the {} element tests of the study: NAME.csv (curve), NAME.json (summary: "
        "material, e0 and its convention, void ratio used, peak), `summary.md`, `summary.csv`, "
        "and `case.toml`, the case that was run (examples/study_calibration.toml); "
        "`pilempm element run tests/case.toml --out DIR` runs it again.\n\n",
        report_.tests_run);
    md += "## Figures\n\n";
    if (report_.plots.plotted)
      md += fmt::format("Drawn with {} and matplotlib. ", report_.plots.python);
    md += fmt::format(
        "To draw them again (e.g. after editing `figures.json`), in this "
        "folder:\n\n```sh\n{}\n```\n",
        plot_command());
    return md;
  }

  static std::string anchor(std::size_t index) { return fmt::format("item-{}", index + 1); }
  std::size_t failed_items() const {
    std::size_t n = 0;
    for (const StudyItem& item : report_.items) n += item.ok ? 0 : 1;
    return n;
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
  std::vector<std::string> names;
  for (const auto& set : kOedometerSets)
    for (const auto& e0 : kOedometerE0) names.push_back(oedometer_name(set, e0));
  names =
      joined({names, kCyclic, kTriaxialDense, kTriaxialLoose, kTriaxialDeltares, kHighPressure});
  for (const std::string& name : kAlphaSensitivity)
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  for (const auto& pair : {kModified, kOriginal, kStressDependent}) {
    names.push_back(pair.second);
    names.push_back(pair.first);
  }
  return names;
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
