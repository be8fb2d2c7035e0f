// Item 8 (beyond the study, docs/study.md §5): the stress-dependent alpha option against the
// original set at 0.1 MPa and the modified set at 10 MPa.
#include <fmt/format.h>

#include <cmath>

#include "pilempm/io/output/format.hpp"
#include "pilempm/study/calibration/figure_parts.hpp"
#include "pilempm/study/calibration/item.hpp"
#include "pilempm/study/calibration/study_tests.hpp"
#include "pilempm/study/calibration/tables.hpp"

namespace pilempm::study::calibration {

namespace {

// The option's peak against the set it should match at one cell pressure.
StressDependentRow compare(const TestResults& tests, const std::string& option,
                           const std::string& original, const std::string& modified,
                           bool against_original) {
  StressDependentRow row;
  row.sigma3 = tests.sigma3(option);
  row.initial_void_ratio = tests.summary(option).initial_void_ratio;
  row.alpha_at_start =
      tests.test(option).material.hypoplastic().stress_dependence.alpha(row.sigma3);
  row.phi_option_deg = tests.summary(option).phi_at_peak_deg;
  row.phi_original_deg = tests.summary(original).phi_at_peak_deg;
  row.phi_modified_deg = tests.summary(modified).phi_at_peak_deg;
  row.compared_with = against_original ? "original" : "modified";
  row.difference_deg =
      row.phi_option_deg - (against_original ? row.phi_original_deg : row.phi_modified_deg);
  return row;
}

}  // namespace

std::string stress_dependent_alpha(const TestResults& tests, ItemOutput& out,
                                   CalibrationStudyReport& report) {
  const std::vector<std::string> names = {kStressDependent.first, kOriginal.first,
                                          kModified.first,        kStressDependent.second,
                                          kOriginal.second,       kModified.second};
  out.set_convention(convention_of(tests, names));
  out.write_csv("stress_dependent_alpha.csv",
                curves_csv(tests, names, triaxial_columns(), kTriaxialComment));
  const std::vector<std::string> labels = {set_label(tests, kStressDependent.first),
                                           set_label(tests, kOriginal.first),
                                           set_label(tests, kModified.first)};
  out.add_figure(pressure_pair_figure(
      tests, "stress_dependent_alpha.png", "stress_dependent_alpha.csv",
      fmt::format("Stress-dependent α option against the original and the "
                  "modified set, $e_0$ = {} at p = 0",
                  format_value(tests.test(kOriginal.first).initial.e0)),
      {kStressDependent, kOriginal, kModified}, labels, {"black", "C0", "C1"}, {"-", "--", ":"}));

  CsvText csv(
      "pilempm study calibration: peak friction angle of the stress-dependent alpha option "
      "against the original set at low pressure and the modified set at high pressure "
      "(drained triaxial); within_1_deg: |difference| <= 1 deg",
      {"sigma3_kPa", "initial_void_ratio", "alpha_option_at_start", "phi_peak_option_deg",
       "phi_peak_original_deg", "phi_peak_modified_deg", "compared_with", "difference_deg",
       "within_1_deg"});
  std::vector<std::vector<std::string>> rows;
  for (const StressDependentRow& row :
       {compare(tests, kStressDependent.first, kOriginal.first, kModified.first, true),
        compare(tests, kStressDependent.second, kOriginal.second, kModified.second, false)}) {
    const bool within = std::abs(row.difference_deg) <= kStressDependentTolerance;
    csv.add({csv_number(row.sigma3 / kKPa), csv_number(row.initial_void_ratio),
             csv_number(row.alpha_at_start), csv_number(row.phi_option_deg),
             csv_number(row.phi_original_deg), csv_number(row.phi_modified_deg), row.compared_with,
             csv_number(row.difference_deg), within ? "true" : "false"});
    rows.push_back({fmt::format("{:g}", row.sigma3 / kMPa), fixed_number(row.initial_void_ratio, 4),
                    fixed_number(row.alpha_at_start, 4), fixed_number(row.phi_option_deg, 2),
                    fixed_number(row.phi_original_deg, 2), fixed_number(row.phi_modified_deg, 2),
                    row.compared_with, fmt::format("{:+.2f}", row.difference_deg),
                    within ? "yes" : "NO"});
    report.stress_dependent.push_back(row);
  }
  out.write_csv("stress_dependent_alpha_table.csv", csv.text());
  const std::string peaks =
      write_peak_table(tests, out, "stress_dependent_alpha_peaks.csv", names,
                       {labels[0], labels[1], labels[2], labels[0], labels[1], labels[2]});

  const StressDependence& d =
      tests.test(kStressDependent.first).material.hypoplastic().stress_dependence;
  std::string md = fmt::format(
      "Beyond the study (docs/study.md §5): the study concludes that α should fall as the stress "
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
                       rows, 0) +
        "\n";
  md += image("stress_dependent_alpha.png", "stress-dependent alpha option");
  md += peaks;
  return md;
}

}  // namespace pilempm::study::calibration
