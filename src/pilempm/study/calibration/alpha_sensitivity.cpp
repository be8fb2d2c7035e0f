// Item 6: drained triaxial at 6 MPa with the original set and alpha changed alone.
#include <fmt/format.h>

#include "pilempm/io/output/format.hpp"
#include "pilempm/study/calibration/figure_parts.hpp"
#include "pilempm/study/calibration/item.hpp"
#include "pilempm/study/calibration/study_tests.hpp"
#include "pilempm/study/calibration/tables.hpp"

namespace pilempm::study::calibration {

std::string alpha_sensitivity(const TestResults& tests, ItemOutput& out, CalibrationStudyReport&) {
  out.set_convention(convention_of(tests, kAlphaSensitivity));
  out.write_csv("alpha_sensitivity.csv",
                curves_csv(tests, kAlphaSensitivity, triaxial_columns(), kTriaxialComment));
  FigureSpec fig;
  fig.file = "alpha_sensitivity.png";
  fig.title = fmt::format(
      "Drained triaxial at $\\sigma'_3$ = {:g} MPa, $e_0$ = {} at p = 0 (R_D = 95 %): "
      "sensitivity to α",
      tests.sigma3(kAlphaSensitivity[0]) / kMPa,
      format_value(tests.test(kAlphaSensitivity[0]).initial.e0));
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
    const ElementCase& c = tests.test(kAlphaSensitivity[k]);
    const std::string label = fmt::format("α = {:g}", c.material.hypoplastic().alpha);
    labels.push_back(label);
    q.series.push_back(curve_series("alpha_sensitivity.csv", c.name, "axial_strain_pct", "q_MPa",
                                    label, color(k)));
    v.series.push_back(curve_series("alpha_sensitivity.csv", c.name, "axial_strain_pct",
                                    "volumetric_strain_pct", label, color(k)));
  }
  fig.panels = {std::move(q), std::move(v)};
  out.add_figure(std::move(fig));
  const std::string peaks =
      write_peak_table(tests, out, "alpha_sensitivity_peaks.csv", kAlphaSensitivity, labels);
  std::string md =
      "The original set with α changed alone (α = 0.12 is the original set itself, the 6 MPa "
      "test of the high-pressure series). α scales the pyknotropy factor f_d: a smaller α "
      "gives less peak strength and less dilation at the same density.\n\n";
  md += image("alpha_sensitivity.png", "alpha sensitivity");
  md += peaks;
  return md;
}

}  // namespace pilempm::study::calibration
