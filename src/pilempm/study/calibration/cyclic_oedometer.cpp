// Item 3: cyclic oedometer with each intergranular strain set and without: initial stiffness,
// reloading stiffness and the strain the cycles accumulate (study/oedometer_stiffness.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <variant>

#include "pilempm/io/output/format.hpp"
#include "pilempm/study/calibration/figure_parts.hpp"
#include "pilempm/study/calibration/item.hpp"
#include "pilempm/study/calibration/study_tests.hpp"
#include "pilempm/study/calibration/tables.hpp"
#include "pilempm/study/oedometer_stiffness.hpp"

namespace pilempm::study::calibration {

namespace {

// The stiffness of one test's curve: vertical stress [Pa] against vertical strain [-].
CyclicOedometerStiffness analyse(const TestResults& tests, const std::string& name) {
  const std::vector<CurvePoint>& curve = tests.curve(name);
  std::vector<double> stress, strain;
  for (const CurvePoint& c : curve) {
    stress.push_back(c.axial_stress);
    strain.push_back(c.axial_strain);
  }
  return analyse_cyclic_oedometer(stress, strain);
}

// The stiffness table: CSV text and Markdown rows; the rows of the report too.
std::string stiffness_csv(const TestResults& tests, const CyclicOedometerStiffness& reference,
                          std::vector<std::vector<std::string>>& rows,
                          CalibrationStudyReport& report) {
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
  for (const std::string& name : kCyclic) {
    const ElementCase& c = tests.test(name);
    CyclicStiffnessRow row;
    row.test = name;
    row.igs = c.igs ? c.igs->name : "none";
    row.stiffness = analyse(tests, name);
    const CyclicOedometerStiffness& s = row.stiffness;
    row.initial_secant_ratio = s.initial_secant_modulus / reference.initial_secant_modulus;
    row.first_increment_ratio = s.first_increment_modulus / reference.first_increment_modulus;
    const IntergranularStrainParameters g =
        c.igs ? c.igs->parameters : IntergranularStrainParameters{};
    // The IGS parameters do not exist without IGS: empty cells.
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
    rows.push_back({row.igs,
                    g.enabled() ? fmt::format("{:g}, {:g}, {:g}, {:g}, {:g}", g.m_R, g.m_T, g.R,
                                              g.beta_r, g.chi)
                                : "–",
                    fixed_number(s.initial_secant_modulus / kMPa, 2),
                    fixed_number(row.initial_secant_ratio, 3),
                    fixed_number(s.first_increment_modulus / kMPa, 2),
                    fixed_number(row.first_increment_ratio, 3),
                    fixed_number(s.reload_secant_modulus / kMPa, 1),
                    fixed_number(100.0 * s.strain_after_first_loading, 4),
                    fixed_number(100.0 * s.accumulated_strain, 4)});
    report.cyclic_stiffness.push_back(row);
  }
  return csv.text();
}

}  // namespace

std::string cyclic_oedometer(const TestResults& tests, ItemOutput& out,
                             CalibrationStudyReport& report) {
  out.set_convention(convention_of(tests, kCyclic));
  out.write_csv("cyclic_oedometer.csv",
                curves_csv(tests, kCyclic, oedometer_columns(), kCurveComment));
  // Stiffness of each, compared with the one without intergranular strain.
  const CyclicOedometerStiffness s0 = analyse(tests, kCyclicReference);
  std::vector<std::vector<std::string>> rows;
  out.write_csv("cyclic_oedometer_stiffness.csv", stiffness_csv(tests, s0, rows, report));

  // Zoom of the second panel: the first loading up to five times the initial stress.
  const double zoom_stress = 5.0 * s0.initial_stress;
  double zoom_strain = 0.0;  // [%]
  for (const std::string& name : kCyclic)
    for (const CurvePoint& c : tests.curve(name))
      if (c.axial_stress >= zoom_stress) {
        zoom_strain = std::max(zoom_strain, 100.0 * c.axial_strain);
        break;
      }
  FigureSpec fig;
  fig.file = "cyclic_oedometer.png";
  fig.title = "Cyclic oedometer, original set: intergranular strain sets and the basic model";
  fig.cols = 2;
  fig.width_in = 13.0;
  fig.height_in = 5.2;
  PanelSpec whole, zoom;
  const OedometerTest& programme = std::get<OedometerTest>(tests.test(kCyclic[0]).test);
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
    const ElementCase& c = tests.test(kCyclic[k]);
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
  out.add_figure(std::move(fig));

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
                       rows, 2) +
        "\n";
  return md;
}

}  // namespace pilempm::study::calibration
