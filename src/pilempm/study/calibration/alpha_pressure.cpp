// Item 5: alpha against p after Herle & Gudehus (1999) with the original set, in both void-ratio
// conventions, beside the stress-dependent alpha law of the model (analytical: no element test).
#include <fmt/format.h>

#include <cmath>

#include "pilempm/analytic/herle_gudehus.hpp"
#include "pilempm/io/output/format.hpp"
#include "pilempm/study/calibration/figure_parts.hpp"
#include "pilempm/study/calibration/item.hpp"
#include "pilempm/study/calibration/study_tests.hpp"
#include "pilempm/study/calibration/tables.hpp"

namespace pilempm::study::calibration {

namespace {

const std::vector<VoidRatioConvention> kConventions = {VoidRatioConvention::at_initial_stress,
                                                       VoidRatioConvention::at_zero_pressure};

std::string series_name(double e0, VoidRatioConvention c) {
  return fmt::format("e0={} {}", format_value(e0), convention_name(c));
}

// The figure: the four Herle & Gudehus curves, the option's law and the two sets' constants.
FigureSpec alpha_figure(const StressDependence& law, double alpha_original, double alpha_modified) {
  FigureSpec fig;
  fig.file = "alpha_pressure.png";
  fig.title = "Exponent α against mean pressure: Herle & Gudehus with Bolton, original set";
  fig.width_in = 10.0;
  fig.height_in = 6.0;
  PanelSpec panel;
  panel.x = {"mean effective stress $p'$ [kPa] (log scale)", true, {}};
  panel.y = {"exponent α [-]", false, {}};
  panel.legend = "upper right";
  for (VoidRatioConvention c : kConventions)
    for (std::size_t k = 0; k < kAlphaVoidRatios.size(); ++k) {
      const double e0 = kAlphaVoidRatios[k];
      SeriesStyle style;
      style.color = color(k);
      style.linestyle = c == VoidRatioConvention::at_initial_stress ? "-" : "--";
      style.linewidth = 1.8;
      panel.series.push_back(
          curve("alpha_pressure.csv", {{"series", series_name(e0, c)}}, "p_kPa", "alpha",
                c == VoidRatioConvention::at_initial_stress
                    ? fmt::format("Herle & Gudehus, e = {} at every p", format_value(e0))
                    : fmt::format("Herle & Gudehus, $e_0$ = {} at p = 0 (Bauer)", format_value(e0)),
                style));
    }
  const auto law_series = [](const std::string& y, const std::string& label,
                             const std::string& colour, const std::string& linestyle,
                             double width) {
    SeriesStyle style;
    style.color = colour;
    style.linestyle = linestyle;
    style.linewidth = width;
    return curve("alpha_pressure_law.csv", {}, "p_kPa", y, label, style);
  };
  panel.series.push_back(law_series("alpha_stress_dependent_option",
                                    fmt::format("stress-dependent α option (defaults: {:g} → {:g})",
                                                law.alpha_low, law.alpha_high),
                                    "black", "-", 2.6));
  panel.series.push_back(law_series("alpha_original_set",
                                    fmt::format("original set, α = {:g}", alpha_original), "grey",
                                    ":", 1.4));
  panel.series.push_back(law_series("alpha_modified_set",
                                    fmt::format("modified set, α = {:g}", alpha_modified), "grey",
                                    "-.", 1.4));
  fig.panels.push_back(std::move(panel));
  return fig;
}

}  // namespace

std::string alpha_pressure(const TestResults&, ItemOutput& out, CalibrationStudyReport& report) {
  const HypoplasticParameters original = hypoplastic_set("original");
  const StressDependence law{};  // the option's defaults
  out.set_convention(
      "both, as two families of curves: `initial-stress`, e = e0 at every p (solid; the "
      "void ratio of the state considered, the recipe that gives α ≈ 0.13 at 100 kPa for e = "
      "0.68), and `zero-pressure`, e0 at p = 0 compressed along Bauer's law e = e0 "
      "exp[−(3p/h_s)^n] (dashed; I_D then stays constant)");
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
  for (VoidRatioConvention c : kConventions)
    for (double e0 : kAlphaVoidRatios)
      for (const AlphaPoint& a : alpha_curve(original, e0, c, grid))
        csv.add({series_name(e0, c), csv_number(e0), convention_name(c),
                 csv_number(a.mean_stress / kKPa), csv_number(a.void_ratio), csv_number(a.e_d),
                 csv_number(a.e_c), csv_number(a.relative_density),
                 a.phi_p_deg ? csv_number(*a.phi_p_deg) : "", a.alpha ? csv_number(*a.alpha) : "",
                 std::string(to_string(a.status))});
  out.write_csv("alpha_pressure.csv", csv.text());
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
  out.write_csv("alpha_pressure_law.csv", law_csv.text());

  // The table at round pressures (the structured result of the report too).
  std::vector<double> table_pressures;
  for (double p : kAlphaTablePressuresKPa) table_pressures.push_back(p * kKPa);
  std::vector<std::string> header = {"p [kPa]"};
  std::vector<std::vector<std::string>> rows(table_pressures.size());
  for (std::size_t i = 0; i < table_pressures.size(); ++i)
    rows[i].push_back(fmt::format("{:g}", table_pressures[i] / kKPa));
  for (VoidRatioConvention c : kConventions)
    for (double e0 : kAlphaVoidRatios) {
      AlphaPressureSeries series{e0, c, alpha_curve(original, e0, c, table_pressures)};
      header.push_back(c == VoidRatioConvention::at_initial_stress
                           ? fmt::format("α, e = {} at every p", format_value(e0))
                           : fmt::format("α, e0 = {} at p = 0", format_value(e0)));
      for (std::size_t i = 0; i < series.points.size(); ++i) {
        const AlphaPoint& a = series.points[i];
        rows[i].push_back(a.alpha ? fixed_number(*a.alpha, 4)
                                  : (a.status == AlphaStatus::no_peak
                                         ? std::string("no peak")
                                         : std::string(to_string(a.status))));
      }
      report.alpha_pressure.push_back(std::move(series));
    }
  header.push_back("α of the option");
  for (std::size_t i = 0; i < table_pressures.size(); ++i)
    rows[i].push_back(fixed_number(law.alpha(table_pressures[i]), 4));
  out.add_figure(alpha_figure(law, original.alpha, alpha_modified));

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
  md += markdown_table(header, rows, 0) + "\n";
  return md;
}

}  // namespace pilempm::study::calibration
