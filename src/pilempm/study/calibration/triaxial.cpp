// Item 2: the drained triaxial calibration tests (dense, loose, and the Deltares samples).
#include <fmt/format.h>

#include <utility>

#include "pilempm/io/output/format.hpp"
#include "pilempm/study/calibration/figure_parts.hpp"
#include "pilempm/study/calibration/item.hpp"
#include "pilempm/study/calibration/study_tests.hpp"
#include "pilempm/study/calibration/tables.hpp"

namespace pilempm::study::calibration {

std::string triaxial(const TestResults& tests, ItemOutput& out, CalibrationStudyReport&) {
  const std::vector<std::pair<std::string, std::vector<std::string>>> groups = {
      {"dense", kTriaxialDense}, {"loose", kTriaxialLoose}, {"Deltares", kTriaxialDeltares}};
  std::vector<std::string> names;
  for (const auto& [group, members] : groups)
    names.insert(names.end(), members.begin(), members.end());
  out.set_convention(convention_of(tests, names));
  out.write_csv("triaxial.csv", curves_csv(tests, names, triaxial_columns(), kTriaxialComment));

  const ElementCase& first = tests.test(names[0]);
  FigureSpec fig;
  fig.file = "triaxial.png";
  fig.title = fmt::format("Drained triaxial compression, set {}, intergranular strain {}",
                          first.material.name, first.igs ? first.igs->name : "none");
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
      const ElementCase& c = tests.test(members[k]);
      const std::string label =
          fmt::format("$\\sigma'_3$ = {:g} kPa, $e_0$ = {}", tests.sigma3(members[k]) / kKPa,
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
  out.add_figure(std::move(fig));
  const std::string peaks = write_peak_table(tests, out, "triaxial_peaks.csv", names, labels);
  std::string md =
      "Drained triaxial compression at constant cell pressure σ'_3 (also the isotropic "
      "consolidation stress) of the laboratory calibration series: dense, loose, and the two "
      "samples of the Deltares set at 200 kPa. Negative volumetric strain is dilation.\n\n";
  md += image("triaxial.png", "drained triaxial curves");
  md += peaks;
  return md;
}

}  // namespace pilempm::study::calibration
