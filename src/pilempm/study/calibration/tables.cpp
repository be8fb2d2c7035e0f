#include "pilempm/study/calibration/tables.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>

#include "pilempm/io/output/format.hpp"
#include "pilempm/study/calibration/study_tests.hpp"

namespace pilempm::study::calibration {

// The expressions of curve_csv (io/element_output.cpp), so that a copied column prints as the
// test's own curve file does.
const std::vector<CurveColumn>& triaxial_columns() {
  static const std::vector<CurveColumn> columns = {
      {"axial_strain_pct", [](const CurvePoint& c) { return 100.0 * c.axial_strain; }},
      {"volumetric_strain_pct", [](const CurvePoint& c) { return 100.0 * c.volumetric_strain; }},
      {"q_kPa", [](const CurvePoint& c) { return c.q / kKPa; }},
      {"q_MPa", [](const CurvePoint& c) { return c.q / kMPa; }},
      {"p_kPa", [](const CurvePoint& c) { return c.p / kKPa; }},
      {"sigma_1_kPa", [](const CurvePoint& c) { return c.axial_stress / kKPa; }},
      {"sigma_3_kPa", [](const CurvePoint& c) { return c.radial_stress / kKPa; }},
      {"void_ratio", [](const CurvePoint& c) { return c.void_ratio; }},
      {"phi_mob_deg", [](const CurvePoint& c) { return c.phi_mobilised_deg; }}};
  return columns;
}

const std::vector<CurveColumn>& oedometer_columns() {
  static const std::vector<CurveColumn> columns = {
      {"vertical_strain_pct", [](const CurvePoint& c) { return 100.0 * c.axial_strain; }},
      {"sigma_v_kPa", [](const CurvePoint& c) { return c.axial_stress / kKPa; }},
      {"sigma_h_kPa", [](const CurvePoint& c) { return c.radial_stress / kKPa; }},
      {"p_kPa", [](const CurvePoint& c) { return c.p / kKPa; }},
      {"void_ratio", [](const CurvePoint& c) { return c.void_ratio; }},
      {"igs_rho", [](const CurvePoint& c) { return c.igs_ratio; }}};
  return columns;
}

const char* const kCurveComment =
    "pilempm study calibration: one row per increment and test; compression positive; strains "
    "logarithmic, in percent; e0_at: the convention of e0, initial_void_ratio: the void ratio "
    "actually used at the start";
const char* const kTriaxialComment =
    "pilempm study calibration: drained triaxial compression at constant cell pressure, one row "
    "per increment and test; compression positive (volumetric strain > 0 is contraction); "
    "strains logarithmic, in percent; q = sigma_1 - sigma_3; e0_at: the convention of e0, "
    "initial_void_ratio: the void ratio actually used at the start";

std::string curves_csv(const TestResults& tests, const std::vector<std::string>& names,
                       const std::vector<CurveColumn>& columns, const char* comment) {
  std::vector<std::string> header = {"test", "set", "igs", "e0", "e0_at", "initial_void_ratio"};
  for (const CurveColumn& column : columns) header.push_back(column.name);
  CsvText csv(comment, header);
  for (const std::string& name : names) {
    const ElementRunRecord& r = tests.record(name);
    const ElementCase& c = *r.test;
    const std::vector<std::string> identity = {c.name,
                                               c.material.name,
                                               c.igs ? c.igs->name : "none",
                                               csv_number(c.initial.e0),
                                               convention_name(c.initial.e0_at),
                                               csv_number(r.summary.initial_void_ratio)};
    for (const CurvePoint& point : r.curve) {
      std::vector<std::string> cells = identity;
      for (const CurveColumn& column : columns)
        cells.push_back(csv_number(column.value(point), kCurveDigits));
      csv.add(cells);
    }
  }
  return csv.text();
}

std::string write_peak_table(const TestResults& tests, ItemOutput& out, const std::string& file,
                             const std::vector<std::string>& names,
                             const std::vector<std::string>& labels) {
  CsvText csv(
      "pilempm study calibration: peak of q of each drained triaxial test; compression "
      "positive; psi after Schanz & Vermeer from d eps_v/d eps_1 at the peak; peak_at_end = "
      "true: q still rose at the end (no peak)",
      {"test", "series", "set", "sigma3_kPa", "e0", "e0_at", "initial_void_ratio", "peak_q_kPa",
       "axial_strain_at_peak_pct", "phi_peak_deg", "dilatancy_ratio_at_peak", "psi_peak_deg",
       "peak_at_end"});
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const ElementRunRecord& r = tests.record(names[i]);
    const ElementCase& c = *r.test;
    const ElementSummary& s = r.summary;
    const double sigma3 = tests.sigma3(names[i]);
    csv.add({c.name, labels[i], c.material.name, csv_number(sigma3 / kKPa),
             csv_number(c.initial.e0), convention_name(c.initial.e0_at),
             csv_number(s.initial_void_ratio), csv_number(s.peak_q / kKPa),
             csv_number(100.0 * s.axial_strain_at_peak), csv_number(s.phi_at_peak_deg),
             csv_number(s.dilatancy_ratio_at_peak), csv_number(s.psi_at_peak_deg),
             s.peak_at_end ? "true" : "false"});
    rows.push_back({labels[i], c.material.name, fmt::format("{:g}", sigma3 / kKPa), e0_text(c),
                    fixed_number(s.initial_void_ratio, 4),
                    shown_number(s.peak_q / kKPa, "{:.6g}") + (s.peak_at_end ? " (end)" : ""),
                    fixed_number(100.0 * s.axial_strain_at_peak, 2),
                    fixed_number(s.phi_at_peak_deg, 2), fixed_number(s.psi_at_peak_deg, 2)});
  }
  out.write_csv(file, csv.text());
  static const std::vector<std::string> header = {"series",          "set",        "σ3 [kPa]",
                                                  "e0 (convention)", "e at start", "peak q [kPa]",
                                                  "ε1 at peak [%]",  "φ peak [°]", "ψ peak [°]"};
  return markdown_table(header, rows, 2) + "\n";
}

std::string e0_text(const ElementCase& c) {
  return fmt::format(
      "{} ({})", format_value(c.initial.e0),
      c.initial.e0_at == VoidRatioConvention::at_zero_pressure ? "at p = 0" : "at initial stress");
}

std::string convention_name(VoidRatioConvention c) {
  return std::string(to_string(c));
}

std::string convention_of(const TestResults& tests, const std::vector<std::string>& names) {
  std::set<VoidRatioConvention> used;
  double e_lo = 1e9, e_hi = -1e9;
  for (const std::string& name : names) {
    used.insert(tests.test(name).initial.e0_at);
    e_lo = std::min(e_lo, tests.summary(name).initial_void_ratio);
    e_hi = std::max(e_hi, tests.summary(name).initial_void_ratio);
  }
  const std::string range =
      e_lo == e_hi ? fixed_number(e_lo, 4)
                   : fmt::format("{} … {}", fixed_number(e_lo, 4), fixed_number(e_hi, 4));
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

}  // namespace pilempm::study::calibration
