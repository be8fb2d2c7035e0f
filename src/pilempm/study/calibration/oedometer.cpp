// Item 1: oedometer curves of the original set (h_s = 4 GPa) and the loose-fit set (2 GPa).
#include <fmt/format.h>

#include <variant>

#include "pilempm/io/output/format.hpp"
#include "pilempm/study/calibration/figure_parts.hpp"
#include "pilempm/study/calibration/item.hpp"
#include "pilempm/study/calibration/study_tests.hpp"
#include "pilempm/study/calibration/tables.hpp"

namespace pilempm::study::calibration {

std::string oedometer(const TestResults& tests, ItemOutput& out, CalibrationStudyReport&) {
  const std::vector<std::string> names = oedometer_names();
  out.set_convention(convention_of(tests, names));
  out.write_csv("oedometer.csv", curves_csv(tests, names, oedometer_columns(), kCurveComment));

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
    const ElementCase& first = tests.test(oedometer_name(kOedometerSets[s], kOedometerE0[0]));
    const double h_s = first.material.hypoplastic().h_s;
    const double sigma_end = tests.summary(first.name).final.axial_stress;
    PanelSpec panel;
    panel.title = fmt::format("$h_s$ = {:g} GPa (set {})", h_s / 1e9, first.material.name);
    panel.x = {"vertical effective stress $\\sigma'_v$ [kPa] (log scale)", true, {}};
    panel.y = {"void ratio e [-]", false, {}};
    header.push_back(fmt::format("e at {:g} kPa, h_s = {:g} GPa", sigma_end / kKPa, h_s / 1e9));
    header.push_back(fmt::format("Δe, h_s = {:g} GPa", h_s / 1e9));
    for (std::size_t k = 0; k < kOedometerE0.size(); ++k) {
      const std::string name = oedometer_name(kOedometerSets[s], kOedometerE0[k]);
      const ElementRunRecord& r = tests.record(name);
      panel.series.push_back(
          curve_series("oedometer.csv", name, "sigma_v_kPa", "void_ratio",
                       "initial void ratio $e_0$ = " + format_value(r.test->initial.e0), color(k)));
      if (s == 0) rows[k].push_back(format_value(r.test->initial.e0));
      rows[k].push_back(fixed_number(r.summary.final.void_ratio, 4));
      rows[k].push_back(fixed_number(r.summary.final.void_ratio - r.summary.initial_void_ratio, 4));
    }
    fig.panels.push_back(std::move(panel));
  }
  out.add_figure(std::move(fig));
  const ElementCase& c = tests.test(names[0]);
  const OedometerTest& programme = std::get<OedometerTest>(c.test);
  std::string md = fmt::format(
      "One-dimensional compression from σ'_v0 = {:g} kPa (σ'_h0 = K0 σ'_v0, K0 = {:g}) to "
      "{:g} kPa, intergranular strain {}, for the dense to loose initial void ratios of the "
      "study, with the "
      "original set (h_s = 4 GPa) and the loose-fit set (h_s = 2 GPa, otherwise equal). The "
      "softer h_s compresses every sample more.\n\n",
      programme.sigma_v0 / kKPa, programme.K0, programme.sigma_v_targets.back() / kKPa,
      c.igs ? c.igs->name : "none");
  md += image("oedometer.png", "oedometer curves");
  md += markdown_table(header, rows) + "\n";
  return md;
}

}  // namespace pilempm::study::calibration
