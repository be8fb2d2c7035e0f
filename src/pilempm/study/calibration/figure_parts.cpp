#include "pilempm/study/calibration/figure_parts.hpp"

#include <fmt/format.h>

#include "pilempm/study/calibration/study_tests.hpp"

namespace pilempm::study::calibration {

std::string color(std::size_t index) {
  return fmt::format("C{}", index % 10);
}

SeriesSpec curve_series(const std::string& csv, const std::string& test, const std::string& x,
                        const std::string& y, const std::string& label, const std::string& colour,
                        const std::string& linestyle, double linewidth) {
  SeriesStyle style;
  style.color = colour;
  style.linestyle = linestyle;
  style.linewidth = linewidth;
  return curve(csv, {{"test", test}}, x, y, label, style);
}

const std::string kAxialStrainLabel = "axial strain $\\varepsilon_1$ [%]";
const std::string kVolumetricStrainLabel = "volumetric strain $\\varepsilon_v$ [%] (contraction +)";
const std::string kDeviatorKPaLabel = "deviator stress $q = \\sigma'_1 - \\sigma'_3$ [kPa]";
const std::string kDeviatorMPaLabel = "deviator stress $q = \\sigma'_1 - \\sigma'_3$ [MPa]";

FigureSpec pressure_pair_figure(const TestResults& tests, const std::string& file,
                                const std::string& csv, const std::string& title,
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
  q_low.title = fmt::format("$\\sigma'_3$ = {:g} MPa", tests.sigma3(pairs[0].first) / kMPa);
  q_high.title = fmt::format("$\\sigma'_3$ = {:g} MPa", tests.sigma3(pairs[0].second) / kMPa);
  q_low.y = {kDeviatorKPaLabel, false, {}};
  q_high.y = {kDeviatorMPaLabel, false, {}};
  v_low.x = v_high.x = {kAxialStrainLabel, false, {}};
  v_low.y = v_high.y = {kVolumetricStrainLabel, false, {}};
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const double width = k == 0 && pairs.size() == 3 ? 2.4 : 1.6;
    q_low.series.push_back(curve_series(csv, pairs[k].first, "axial_strain_pct", "q_kPa", labels[k],
                                        colours[k], styles[k], width));
    q_high.series.push_back(curve_series(csv, pairs[k].second, "axial_strain_pct", "q_MPa",
                                         labels[k], colours[k], styles[k], width));
    v_low.series.push_back(curve_series(csv, pairs[k].first, "axial_strain_pct",
                                        "volumetric_strain_pct", labels[k], colours[k], styles[k],
                                        width));
    v_high.series.push_back(curve_series(csv, pairs[k].second, "axial_strain_pct",
                                         "volumetric_strain_pct", labels[k], colours[k], styles[k],
                                         width));
  }
  fig.panels = {std::move(q_low), std::move(q_high), std::move(v_low), std::move(v_high)};
  return fig;
}

std::string set_label(const TestResults& tests, const std::string& name) {
  const MaterialSpec& m = tests.test(name).material;
  const StressDependence& d = m.hypoplastic().stress_dependence;
  if (d.alpha_varies)
    return fmt::format(
        "{} with stress-dependent α ({:g} → {:g})",
        m.hypoplastic_material().base.empty() ? m.name : m.hypoplastic_material().base, d.alpha_low,
        d.alpha_high);
  return fmt::format("{} set (φc = {:g}°, α = {:g})", m.name, m.hypoplastic().phi_c_deg,
                     m.hypoplastic().alpha);
}

std::string image(const std::string& file, const std::string& alt) {
  return fmt::format("![{}]({})\n\n", alt, file);
}

}  // namespace pilempm::study::calibration
