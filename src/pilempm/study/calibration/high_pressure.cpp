// Item 4: high-pressure drained triaxial beside Bolton (1986) at p' = sigma3, as the study's
// table (docs/study.md §3.1).
#include <fmt/format.h>

#include "pilempm/analytic/bolton.hpp"
#include "pilempm/io/output/format.hpp"
#include "pilempm/study/calibration/figure_parts.hpp"
#include "pilempm/study/calibration/item.hpp"
#include "pilempm/study/calibration/study_tests.hpp"
#include "pilempm/study/calibration/tables.hpp"

namespace pilempm::study::calibration {

namespace {

// The peaks against cell pressure: model and Bolton.
FigureSpec peaks_figure() {
  FigureSpec peaks;
  peaks.file = "high_pressure_peaks.png";
  peaks.title = "Peak friction and dilatancy angles against cell pressure: model and Bolton";
  peaks.cols = 2;
  peaks.width_in = 12.0;
  peaks.height_in = 5.0;
  const auto table_series = [](const std::string& y, const std::string& label,
                               const std::string& colour, const std::string& style,
                               const std::string& marker) {
    SeriesStyle s;
    s.color = colour;
    s.linestyle = style;
    s.marker = marker;
    s.markersize = marker.empty() ? 0.0 : 6.0;
    return curve("high_pressure_table.csv", {}, "sigma3_MPa", y, label, s);
  };
  const std::string bolton_label =
      fmt::format("Bolton (1986), $I_D$ = {:g}, $p'$ = $\\sigma'_3$", kBoltonRelativeDensity);
  PanelSpec pphi, ppsi;
  pphi.title = "peak friction angle";
  ppsi.title = "dilatancy angle at the peak";
  pphi.x = ppsi.x = {"cell pressure $\\sigma'_3$ [MPa] (log scale)", true, {}};
  pphi.y = {"friction angle $\\varphi$ [°]", false, {}};
  ppsi.y = {"dilatancy angle $\\psi$ [°] (negative: contraction)", false, {}};
  pphi.series = {table_series("phi_peak_deg", "hypoplastic model, peak", "C0", "-", "o"),
                 table_series("bolton_phi_max_deg", bolton_label, "C3", "--", "s"),
                 table_series("bolton_phi_c_deg", fmt::format("$\\varphi_c$ = {:g}°", kBoltonPhiC),
                              "grey", ":", "")};
  ppsi.series = {table_series("psi_peak_deg", "hypoplastic model, at the peak", "C0", "-", "o"),
                 table_series("bolton_psi_max_deg", bolton_label, "C3", "--", "s")};
  pphi.legend = ppsi.legend = "lower left";
  peaks.panels = {std::move(pphi), std::move(ppsi)};
  return peaks;
}

}  // namespace

std::string high_pressure(const TestResults& tests, ItemOutput& out,
                          CalibrationStudyReport& report) {
  out.set_convention(convention_of(tests, kHighPressure));
  out.write_csv("high_pressure_triaxial.csv",
                curves_csv(tests, kHighPressure, triaxial_columns(), kTriaxialComment));
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
    const ElementRunRecord& r = tests.record(name);
    HighPressureRow row;
    row.test = name;
    row.sigma3 = tests.sigma3(name);
    row.initial_void_ratio = r.summary.initial_void_ratio;
    row.peak_q = r.summary.peak_q;
    row.axial_strain_at_peak = r.summary.axial_strain_at_peak;
    row.phi_peak_deg = r.summary.phi_at_peak_deg;
    row.psi_peak_deg = r.summary.psi_at_peak_deg;
    row.peak_at_end = r.summary.peak_at_end;
    row.bolton = bolton(kBoltonRelativeDensity, kBoltonPhiC, row.sigma3);
    csv.add({name, csv_number(row.sigma3 / kKPa), csv_number(row.sigma3 / kMPa),
             csv_number(r.test->initial.e0), convention_name(r.test->initial.e0_at),
             csv_number(row.initial_void_ratio), csv_number(row.peak_q / kKPa),
             csv_number(100.0 * row.axial_strain_at_peak), csv_number(row.phi_peak_deg),
             csv_number(row.psi_peak_deg), row.peak_at_end ? "true" : "false",
             csv_number(kBoltonRelativeDensity), csv_number(kBoltonPhiC),
             csv_number(row.sigma3 / kKPa), csv_number(row.bolton.relative_dilatancy_index),
             csv_number(row.bolton.phi_max_deg), csv_number(row.bolton.dilatancy_rate),
             csv_number(row.bolton.psi_max_deg)});
    rows.push_back(
        {fmt::format("{:g}", row.sigma3 / kMPa), fixed_number(row.initial_void_ratio, 4),
         shown_number(row.peak_q / kMPa, "{:.4g}") + (row.peak_at_end ? " (end)" : ""),
         fixed_number(100.0 * row.axial_strain_at_peak, 2), fixed_number(row.phi_peak_deg, 2),
         fixed_number(row.psi_peak_deg, 2), fixed_number(row.bolton.relative_dilatancy_index, 3),
         fixed_number(row.bolton.phi_max_deg, 3), fixed_number(row.bolton.psi_max_deg, 3)});
    report.high_pressure.push_back(row);
  }
  out.write_csv("high_pressure_table.csv", csv.text());

  const ElementCase& first = tests.test(kHighPressure[0]);
  FigureSpec curves;
  curves.file = "high_pressure_triaxial.png";
  curves.title =
      fmt::format("High-pressure drained triaxial, set {}, $e_0$ = {} at p = 0 (R_D = 95 %)",
                  first.material.name, format_value(first.initial.e0));
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
        fmt::format("$\\sigma'_3$ = {:g} MPa", tests.sigma3(kHighPressure[k]) / kMPa);
    phi.series.push_back(curve_series("high_pressure_triaxial.csv", kHighPressure[k],
                                      "axial_strain_pct", "phi_mob_deg", label, color(k)));
    v.series.push_back(curve_series("high_pressure_triaxial.csv", kHighPressure[k],
                                    "axial_strain_pct", "volumetric_strain_pct", label, color(k)));
  }
  curves.panels = {std::move(phi), std::move(v)};
  out.add_figure(std::move(curves));
  out.add_figure(peaks_figure());

  std::string md = fmt::format(
      "Drained triaxial compression of the dense sand (e0 = {} at zero pressure, R_D = 95 %) "
      "at cell pressures up to 30 MPa with the {} set. φ is the mobilised friction angle at "
      "the peak of q (sin φ = (σ1 − σ3)/(σ1 + σ3)), ψ the dilatancy angle from dε_v/dε_1 at "
      "the peak (sin ψ = −(dε_v/dε_1)/(2 − dε_v/dε_1), Schanz & Vermeer). Bolton (1986) with "
      "I_D = {:g}, φc = {:g}° at p' = σ'_3 (as the study's table): I_R = I_D (10 − ln p') − 1, "
      "φ_max = φc + 3 I_R, sin ψ_max = 0.3 I_R/(2 + 0.3 I_R). Bolton's peak falls below φc "
      "(contraction, ψ < 0) at the highest pressures, where the model still dilates at its "
      "peak.\n\n",
      format_value(first.initial.e0), first.material.name, kBoltonRelativeDensity, kBoltonPhiC);
  md += image("high_pressure_peaks.png", "peak angles against pressure");
  md += markdown_table({"σ3 [MPa]", "e at start", "peak q [MPa]", "ε1 at peak [%]", "φ peak [°]",
                        "ψ peak [°]", "Bolton I_R", "Bolton φ_max [°]", "Bolton ψ_max [°]"},
                       rows, 0) +
        "\n";
  md += image("high_pressure_triaxial.png", "high-pressure triaxial curves");
  return md;
}

}  // namespace pilempm::study::calibration
