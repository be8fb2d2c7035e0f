// Item 7: the modified medium-dense set against the original set at 0.1 and 10 MPa.
#include <fmt/format.h>

#include "pilempm/io/output/format.hpp"
#include "pilempm/study/calibration/figure_parts.hpp"
#include "pilempm/study/calibration/item.hpp"
#include "pilempm/study/calibration/study_tests.hpp"
#include "pilempm/study/calibration/tables.hpp"

namespace pilempm::study::calibration {

std::string modified_vs_original(const TestResults& tests, ItemOutput& out,
                                 CalibrationStudyReport&) {
  const std::vector<std::string> names = {kOriginal.first, kModified.first, kOriginal.second,
                                          kModified.second};
  out.set_convention(convention_of(tests, names));
  out.write_csv("modified_vs_original.csv",
                curves_csv(tests, names, triaxial_columns(), kTriaxialComment));
  std::vector<std::string> labels;
  for (const std::string& name : names) labels.push_back(set_label(tests, name));
  out.add_figure(pressure_pair_figure(
      tests, "modified_vs_original.png", "modified_vs_original.csv",
      fmt::format("Original against modified set, $e_0$ = {} at p = 0",
                  format_value(tests.test(kOriginal.first).initial.e0)),
      {kOriginal, kModified}, {labels[0], labels[1]}, {"C0", "C1"}, {"-", "--"}));
  const std::string peaks =
      write_peak_table(tests, out, "modified_vs_original_peaks.csv", names, labels);
  const HypoplasticParameters& m = tests.test(kModified.first).material.hypoplastic();
  std::string md = fmt::format(
      "The modified medium-dense set (φc = {:g}°, e_d0/e_c0/e_i0 = {:g}/{:g}/{:g} after Rohe "
      "at 10 MPa, α = {:g}) against the original set, at σ'_3 = 10 MPa (the stress level "
      "below the pile tip) and 0.1 MPa. The modified set removes most of the peak and the "
      "dilation at both pressures.\n\n",
      m.phi_c_deg, m.e_d0, m.e_c0, m.e_i0, m.alpha);
  md += image("modified_vs_original.png", "modified against original set");
  md += peaks;
  return md;
}

}  // namespace pilempm::study::calibration
