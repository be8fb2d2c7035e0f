#include "pilempm/study/centrifuge_run.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <numbers>
#include <optional>
#include <tuple>

#include "pilempm/constitutive/material_state.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/io/centrifuge_case.hpp"
#include "pilempm/io/mpm_output.hpp"
#include "pilempm/io/mpm_phase_control.hpp"
#include "pilempm/io/output/atomic_file.hpp"
#include "pilempm/io/output/format.hpp"
#include "pilempm/io/output/json_writer.hpp"
#include "pilempm/io/vtu_writer.hpp"
#include "pilempm/study/figures.hpp"
#include "pilempm/study/plotting.hpp"
#include "pilempm/study/quick_centrifuge_case.hpp"

namespace pilempm {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool starts_with(const std::string& text, const std::string& prefix) {
  return text.rfind(prefix, 0) == 0;
}

bool is_installation(const std::string& phase) {
  return starts_with(phase, "installation");
}

// One row of pile.csv, as numbers.
struct PileRow {
  double time = 0.0;
  std::string phase;
  double displacement = 0.0;                      // pile, down positive [m]
  double phase_displacement = 0.0;                // since the phase start, down positive [m]
  double tip_depth = 0.0;                         // below the sand surface [m]
  double head = 0.0, tip = 0.0, shaft = 0.0;      // [N]
  double base_reaction = 0.0, soil_weight = 0.0;  // [N]
  double kinetic = 0.0, pile_work = 0.0;          // [J]
  double momentum_rate = 0.0;  // the sand's vertical momentum (scaled mass): mean dP/dt [N]
  double damping = 0.0;        // the local damping's vertical force on the sand, mean [N]

  // F_head − (R_base − W): zero in static equilibrium, D − dP/dt of the sand in general.
  double equilibrium_residual() const { return head - (base_reaction - soil_weight); }
  // The sand's momentum balance dP/dt = R_base + D − W − F_head, as residual + dP/dt − D: zero
  // when every force on the sand is booked.
  double force_book_closure() const { return equilibrium_residual() + momentum_rate - damping; }
};

// Records pile.csv during the run: one row per record interval of pile travel, and at every
// phase end, each with the forces averaged over the time since the previous row.
class PileRecorder {
 public:
  PileRecorder(const CentrifugeScenario& s, double factor)
      : s_(s), factor_(factor), interval_(s.record_interval_D * s.pile_diameter) {}

  void after_step(const mpm::Solver& solver, const MpmPhase& phase, double dt) {
    means_.add_step(solver, dt);
    reaction_impulse_ += dt * solver.boundary_reaction();
    damping_impulse_ += dt * solver.damping_force();
    elapsed_ += dt;
    // Installation: a row per record interval; the short relaxation and load test: ten.
    const double interval = is_installation(phase.name) ? interval_ : 0.1 * interval_;
    if (phase.name != "initial-stress" &&
        std::abs(pile_y(solver) - last_row_y_) >= interval * (1.0 - 1e-9))
      add_row(solver, phase.name);
  }

  void phase_end(const mpm::Solver& solver, const MpmPhase& phase) {
    if (elapsed_ > 0.0) add_row(solver, phase.name);
    phase_start_y_ = pile_y(solver);
  }

  const std::vector<PileRow>& rows() const { return rows_; }

 private:
  static double pile_y(const mpm::Solver& solver) {
    return solver.rigid_body(0).displacement().y();
  }

  void add_row(const mpm::Solver& solver, const std::string& phase) {
    const std::vector<mpm::RigidBodyForce> forces = means_.take(solver);
    const mpm::RigidBodyForce& f = forces.at(0);
    PileRow row;
    row.time = solver.time();
    row.phase = phase;
    const double y = pile_y(solver);
    row.displacement = 0.0 - y;  // 0 - y: no "-0" in the file
    row.phase_displacement = 0.0 - (y - phase_start_y_);
    row.tip_depth = s_.wished_in_place_D * s_.pile_diameter - y;
    row.head = factor_ * f.total.y();
    row.tip = f.parts.size() > 0 ? factor_ * f.parts[0].y() : 0.0;
    row.shaft = f.parts.size() > 1 ? factor_ * f.parts[1].y() : 0.0;
    row.base_reaction = elapsed_ > 0.0 ? factor_ * reaction_impulse_.y() / elapsed_ : 0.0;
    row.damping = elapsed_ > 0.0 ? factor_ * damping_impulse_.y() / elapsed_ : 0.0;
    if (!soil_weight_) {  // the particles and their masses do not change
      double mass = 0.0;
      for (double m : solver.particles().mass) mass += m;
      soil_weight_ = factor_ * mass * s_.gravity * s_.g_level;
    }
    row.soil_weight = *soil_weight_;
    row.kinetic = factor_ * solver.energies().kinetic;
    row.pile_work = factor_ * solver.energies().contact_work;
    // The sand's vertical momentum with the inertial (scaled) mass; it starts at rest at t = 0.
    const mpm::Particles& particles = solver.particles();
    double momentum = 0.0;
    for (std::size_t p = 0; p < particles.size(); ++p)
      momentum += particles.mass[p] * particles.velocity[p].y();
    momentum *= factor_ * solver.settings().mass_scaling;
    row.momentum_rate = elapsed_ > 0.0 ? (momentum - momentum_) / elapsed_ : 0.0;
    momentum_ = momentum;
    rows_.push_back(row);
    reaction_impulse_ = damping_impulse_ = mpm::Vec2::Zero();
    elapsed_ = 0.0;
    last_row_y_ = y;
  }

  const CentrifugeScenario& s_;
  double factor_;
  double interval_;
  MpmBodyForceMeans means_;
  mpm::Vec2 reaction_impulse_ = mpm::Vec2::Zero();
  mpm::Vec2 damping_impulse_ = mpm::Vec2::Zero();
  double elapsed_ = 0.0;
  double last_row_y_ = 0.0;
  double phase_start_y_ = 0.0;
  double momentum_ = 0.0;              // [N s], at the last row
  std::optional<double> soil_weight_;  // [N], summed at the first row
  std::vector<PileRow> rows_;
};

std::string pile_csv(const std::vector<PileRow>& rows, double D) {
  const double tip_area = std::numbers::pi * 0.25 * D * D;
  std::string text =
      "# the pile: displacement and phase_displacement down positive since it was wished in "
      "place and since the phase start; forces of the soil on the full pile, up positive (a pile "
      "pushed into the sand carries head_force_N > 0), averaged over the time since the previous "
      "row; tip_stress_MPa = tip force / (pi D^2 / 4), the mean normal stress on the projected "
      "tip area; base_reaction_N: the container's vertical reaction on the sand, soil_weight_N: "
      "the sand's weight at N g, equilibrium_residual_N = head - (base - weight); kinetic_J (with "
      "the scaled mass) and pile_work_J (the work of the pile on the sand since t = 0) of the "
      "full model; sand_momentum_rate_N: the change of the sand's vertical momentum (scaled "
      "mass, up positive) over the time since the previous row; damping_force_N: the local "
      "damping's vertical force on the sand (up positive; zero in phases without damping), so "
      "that equilibrium_residual_N + sand_momentum_rate_N - damping_force_N = 0 when the forces "
      "are booked right: the residual is the sand's inertia and the damping\n";
  for (const std::string& column : centrifuge_pile_columns()) {
    text += column;
    text += column == centrifuge_pile_columns().back() ? '\n' : ',';
  }
  for (const PileRow& r : rows)
    text += csv_row({csv_number(r.time, 8), r.phase, csv_number(1e3 * r.displacement, 6),
                     csv_number(1e3 * r.phase_displacement, 6), csv_number(1e3 * r.tip_depth, 6),
                     csv_number(r.tip_depth / D, 6), csv_number(r.head, 6), csv_number(r.tip, 6),
                     csv_number(r.shaft, 6), csv_number(r.tip / tip_area / 1e6, 6),
                     csv_number(r.base_reaction, 6), csv_number(r.soil_weight, 8),
                     csv_number(r.equilibrium_residual(), 8), csv_number(r.kinetic, 6),
                     csv_number(r.pile_work, 6), csv_number(r.phase_displacement / D, 6),
                     csv_number(r.momentum_rate, 8), csv_number(r.damping, 8)});
  return text;
}

// The sand's state as CSV (coordinates from the axis and below the surface).
std::string fields_csv(const mpm::Solver& solver, double surface) {
  const std::vector<double> igs_size = mpm_igs_sizes(solver);
  const mpm::Particles& particles = solver.particles();
  std::string text =
      "# the sand's particles: r_mm from the axis, depth_mm below the initial sand surface, "
      "p and q in kPa (compression positive), igs_rho = ||delta|| / R of the intergranular "
      "strain\nr_mm,depth_mm,void_ratio,p_kPa,q_kPa,igs_rho\n";
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const MaterialState& state = particles.state[p];
    const double R = igs_size[static_cast<std::size_t>(particles.material[p])];
    const double rho =
        R > 0.0 ? std::min(1.0, Vec6(Hypoplastic::intergranular_strain(state)).norm() / R) : 0.0;
    text +=
        csv_row({csv_number(1e3 * particles.position[p].x(), 6),
                 csv_number(1e3 * (surface - particles.position[p].y()), 6),
                 csv_number(state.void_ratio, 6), csv_number(mean_stress(state.stress) / 1e3, 6),
                 csv_number(deviator_stress(state.stress) / 1e3, 6), csv_number(rho, 4)});
  }
  return text;
}

// The K0 check: σ_v against ρ N g z after the initial-stress phase, beyond 2 D from the pile.
void initial_stress_check(const CentrifugeScenario& s, const mpm::Solver& solver,
                          CentrifugeSummary& summary) {
  const double unit = s.sand_density() * s.g_level * s.gravity;  // [Pa/m]
  const double H = s.sand_height();
  double worst = 0.0, ratio_sum = 0.0;
  long count = 0;
  const mpm::Particles& particles = solver.particles();
  for (std::size_t p = 0; p < particles.size(); ++p) {
    if (particles.position[p].x() < 2.0 * s.pile_diameter) continue;
    const double z = H - particles.position[p].y();
    const double sigma_v = -particles.state[p].stress[k22];
    worst = std::max(worst, std::abs(sigma_v - unit * z) / (unit * H));
    if (z > s.pile_diameter) {
      ratio_sum += sigma_v / (unit * z);
      ++count;
    }
  }
  summary.initial_stress_error = worst;
  summary.initial_stress_ratio = count > 0 ? ratio_sum / static_cast<double>(count) : kNaN;
}

// The largest |Σ quantity Δu| / Σ head Δu over consecutive windows of `window` of pile travel u
// during installation, among the windows whose mean head force exceeds `threshold` (NaN if none).
template <class Quantity>
double max_window_ratio(const std::vector<PileRow>& rows, double window, double threshold,
                        const Quantity& quantity) {
  double worst = kNaN, head = 0.0, sum = 0.0, travel = 0.0, previous = 0.0;
  for (const PileRow& r : rows) {
    if (!is_installation(r.phase)) continue;
    const double step = r.displacement - previous;
    previous = r.displacement;
    if (step <= 0.0) continue;
    head += r.head * step;
    sum += quantity(r) * step;
    travel += step;
    if (travel < window * (1.0 - 1e-6)) continue;
    const double ratio = std::abs(sum) / head;
    if (head / travel > threshold && !(ratio <= worst)) worst = ratio;  // NaN: the first window
    head = sum = travel = 0.0;
  }
  return worst;
}

std::string summary_markdown(const CentrifugeScenario& s, const CentrifugeSummary& r) {
  auto value = [](double v, const char* format) { return shown_number(v, format); };
  std::string md = fmt::format("# {}\n\n", r.title);
  md += fmt::format(
      "D = {:g} mm at {:g} g, container R = {:g} D, sand H = {:g} D, e0 = {:g} ({}), set \"{}\" "
      "with {}, pile wished in place at {:g} D, installed {:g} D.\n\n",
      1e3 * s.pile_diameter, s.g_level, s.container_radius_D, s.sand_height_D, s.e0, s.e0_at,
      s.installation_material, s.igs, s.wished_in_place_D, s.installation_D);
  md += "| quantity | value |\n|---|---|\n";
  md += fmt::format(
      "| head force at the end of installation (mean over the last cell of travel) "
      "| {} N at {} D |\n",
      value(r.installation_head_force, "{:.1f}"), value(r.installation_tip_depth_D, "{:.2f}"));
  md += fmt::format("| peak tip stress during installation | {} MPa at {} D |\n",
                    value(r.peak_tip_stress_MPa, "{:.2f}"),
                    value(r.peak_tip_stress_depth_D, "{:.2f}"));
  md += fmt::format("| pile pulled up in relaxation (to zero head force) | {} mm |\n",
                    value(r.relaxation_travel_mm, "{:.3f}"));
  md += fmt::format("| load-test capacity at {} mm | {} N |\n",
                    value(r.load_test_displacement_mm, "{:.3g}"), value(r.capacity, "{:.1f}"));
  md += fmt::format("| K0 stress: max abs(σv − ρNgz) / ρNgH; mean σv / ρNgz | {} %; {} |\n",
                    value(100.0 * r.initial_stress_error, "{:.2f}"),
                    value(r.initial_stress_ratio, "{:.4f}"));
  md += fmt::format(
      "| equilibrium: max abs(F_head − (R_base − W)) / F_head over windows of one cell; of 1 D of "
      "travel, installation | {} %; {} % |\n",
      value(100.0 * r.equilibrium_error, "{:.2f}"),
      value(100.0 * r.equilibrium_error_1D, "{:.2f}"));
  md += fmt::format(
      "| the same with the sand's (scaled) inertia dP/dt added and the damping's force D taken "
      "off: the force book's closure | {} % "
      "|\n",
      value(100.0 * r.equilibrium_closure, "{:.1e}"));
  md += fmt::format("| max kinetic energy / pile work, installation | {} % |\n",
                    value(100.0 * r.max_kinetic_to_work, "{:.3f}"));
  md += fmt::format(
      "| particles passed into the pile (deeper than a cell), at phase ends | {} |\n"
      "| deepest particle centre inside the pile surface | {} cells |\n"
      "| smallest particle radius | {} mm |\n",
      r.particles_in_pile, value(r.max_penetration_cells, "{:.2f}"),
      value(r.min_radius_mm, "{:.3f}"));
  md += fmt::format("| particles; steps; wall time | {}; {}; {:.1f} s |\n", r.particles, r.steps,
                    r.wall_seconds);
  md +=
      "\nFiles: `pile.csv` (forces against displacement and depth), `fields_<phase>.csv` and "
      "`.vtu` (void ratio, p, q, IGS ρ), `mpm/` (the MPM case's own output and checkpoints), "
      "`case.toml`, `mpm_case.toml`";
  if (!r.figures.empty()) md += ", " + fmt::format("`{}`", fmt::join(r.figures, "`, `"));
  md += ".\n";
  if (!r.plot_problem.empty())
    md += fmt::format(
        "\nThe figures were not drawn: {}. Draw them later with `/usr/bin/python3 "
        "plot_figures.py figures.json` in this folder.\n",
        r.plot_problem);
  return md;
}

FigureSpec field_figure(const CentrifugeScenario& s, const std::string& phase) {
  return centrifuge_field_figure(s, phase, "fields_" + phase + ".csv", "fields_" + phase + ".png");
}

std::vector<FigureSpec> run_figures(const CentrifugeScenario& s) {
  std::vector<FigureSpec> figures;
  if (s.installation_D > 0.0) {
    FigureSpec f;
    f.file = "installation.png";
    f.title = s.title;
    f.rows = 1;
    f.cols = 2;
    f.width_in = 11.0;
    f.height_in = 4.5;
    PanelSpec force;
    force.title = "head force during installation";
    force.x.label = "pile displacement [mm]";
    force.y.label = "force [N]";
    // One colour per force; the split installation phases share it, labelled once.
    for (auto [column, label, colour] : {std::tuple{"head_force_N", "head", "C0"},
                                         {"tip_force_N", "tip", "C1"},
                                         {"shaft_force_N", "shaft", "C2"}})
      for (const std::string& phase : scenario_phase_names(s))
        if (is_installation(phase))
          force.series.push_back(curve("pile.csv", {{"phase", phase}}, "pile_displacement_mm",
                                       column, phase == "installation" ? label : "",
                                       SeriesStyle{colour, "-", "", 1.2, 0}));
    f.panels.push_back(force);
    PanelSpec tip;
    tip.title = "tip stress against tip depth";
    tip.x.label = "mean normal stress on the tip [MPa]";
    tip.y.label = "tip depth [D]";
    for (const std::string& phase : scenario_phase_names(s))
      if (is_installation(phase))
        tip.series.push_back(curve("pile.csv", {{"phase", phase}}, "tip_stress_MPa", "tip_depth_D",
                                   "", SeriesStyle{"C3", "-", "", 1.2, 0}));
    tip.legend = "none";
    f.panels.push_back(tip);
    figures.push_back(f);
  }
  if (s.load_test_D > 0.0) {
    FigureSpec f;
    f.file = "load_test.png";
    f.title = s.title + ": static load test";
    PanelSpec panel;
    panel.x.label = "pile displacement in the load test [mm]";
    panel.y.label = "force [N]";
    for (auto [column, label, colour] : {std::tuple{"head_force_N", "head", "C0"},
                                         {"tip_force_N", "tip", "C1"},
                                         {"shaft_force_N", "shaft", "C2"}})
      panel.series.push_back(curve("pile.csv", {{"phase", "load-test"}}, "phase_displacement_mm",
                                   column, label, SeriesStyle{colour, "-", "", 1.4, 0}));
    f.panels.push_back(panel);
    figures.push_back(f);
  }
  for (const std::string& phase : scenario_phase_names(s))
    if (is_installation(phase) || phase == "load-test") figures.push_back(field_figure(s, phase));
  return figures;
}

}  // namespace

FigureSpec centrifuge_field_figure(const CentrifugeScenario& s, const std::string& phase,
                                   const std::string& csv, const std::string& file) {
  FigureSpec f;
  f.file = file;
  f.title = fmt::format("{}: after {}", s.title, phase);
  f.rows = 1;
  f.cols = 4;
  f.width_in = 15.0;
  f.height_in = 6.0;
  const double mm = 1e3 * s.pile_diameter;
  const double deepest = s.wished_in_place_D + s.installation_D;
  // Fixed scales, so that runs can be compared: e from dense to loose, stresses logarithmic
  // from the overburden near the surface to the tip's MPa.
  for (auto [column, label, map, low, high, log] :
       {std::tuple{"void_ratio", "void ratio [-]", "viridis", 0.55, 0.95, false},
        {"p_kPa", "p [kPa]", "magma", 5.0, 5000.0, true},
        {"q_kPa", "q [kPa]", "magma", 5.0, 5000.0, true},
        {"igs_rho", "IGS rho [-]", "cividis", 0.0, 1.0, false}}) {
    PanelSpec panel;
    panel.x.label = "r [mm]";
    panel.y.label = "depth [mm]";
    panel.x.limits = std::pair{0.0, std::min(3.0, s.container_radius_D) * mm};
    panel.y.limits = std::pair{std::max(0.0, deepest - 6.0) * mm, (deepest + 3.0) * mm};
    panel.y.invert = true;
    panel.legend = "none";
    SeriesSpec series = curve(csv, {}, "r_mm", "depth_mm", "", SeriesStyle{"", "", "", 0.0, 3.0});
    series.color_by = column;
    series.color_label = label;
    series.colormap = map;
    series.color_limits = std::pair{low, high};
    series.color_log = log;
    panel.series.push_back(series);
    f.panels.push_back(panel);
  }
  return f;
}

std::string_view quick_centrifuge_case_text() {
  return {reinterpret_cast<const char*>(generated::kQuickCentrifugeCase),
          sizeof generated::kQuickCentrifugeCase};
}

const std::vector<std::string>& centrifuge_pile_columns() {
  static const std::vector<std::string> columns{"time_s",
                                                "phase",
                                                "pile_displacement_mm",
                                                "phase_displacement_mm",
                                                "tip_depth_mm",
                                                "tip_depth_D",
                                                "head_force_N",
                                                "tip_force_N",
                                                "shaft_force_N",
                                                "tip_stress_MPa",
                                                "base_reaction_N",
                                                "soil_weight_N",
                                                "equilibrium_residual_N",
                                                "kinetic_J",
                                                "pile_work_J",
                                                "phase_displacement_D",
                                                "sand_momentum_rate_N",
                                                "damping_force_N"};
  return columns;
}

namespace {

// The numbers of a summary by name, in the order of the files.
std::vector<std::pair<std::string, double>> summary_numbers(const CentrifugeSummary& r) {
  return {{"particles", static_cast<double>(r.particles)},
          {"steps", static_cast<double>(r.steps)},
          {"wall_time_s", r.wall_seconds},
          {"initial_stress_error", r.initial_stress_error},
          {"initial_stress_ratio", r.initial_stress_ratio},
          {"installation_head_force_N", r.installation_head_force},
          {"installation_tip_depth_D", r.installation_tip_depth_D},
          {"peak_tip_stress_MPa", r.peak_tip_stress_MPa},
          {"peak_tip_stress_depth_D", r.peak_tip_stress_depth_D},
          {"relaxation_travel_mm", r.relaxation_travel_mm},
          {"load_test_capacity_N", r.capacity},
          {"load_test_displacement_mm", r.load_test_displacement_mm},
          {"equilibrium_error", r.equilibrium_error},
          {"equilibrium_error_1D", r.equilibrium_error_1D},
          {"equilibrium_closure", r.equilibrium_closure},
          {"max_kinetic_to_work", r.max_kinetic_to_work},
          {"particles_in_pile", static_cast<double>(r.particles_in_pile)},
          {"max_penetration_cells", r.max_penetration_cells},
          {"min_radius_mm", r.min_radius_mm}};
}

}  // namespace

std::string centrifuge_summary_json(const CentrifugeSummary& r) {
  std::string json = "{\n  \"title\": " + json_quote(r.title);
  for (const auto& [key, value] : summary_numbers(r))
    json += fmt::format(",\n  {}: {}", json_quote(key), json_number(value, 6));
  return json + "\n}\n";
}

std::string centrifuge_summary_csv(const CentrifugeSummary& r) {
  std::string header = "# the summary of a centrifuge run (summary.md says what each is)\n";
  std::string row;
  for (const auto& [key, value] : summary_numbers(r)) {
    header += (row.empty() ? "" : ",") + key;
    row += (row.empty() ? "" : ",") + csv_number(value, 8);
  }
  return header + "\n" + row + "\n";
}

CentrifugeSummary run_centrifuge(const CentrifugeScenario& s, const std::string& case_text,
                                 const std::filesystem::path& out_dir, std::ostream* progress,
                                 const CentrifugeRunOptions& options) {
  const std::string mpm_text = centrifuge_mpm_case(s);
  const MpmCase mpm_case = read_mpm_case_text(mpm_text, (out_dir / "mpm_case.toml").string());
  prepare_output_directory(out_dir);
  if (!case_text.empty()) write_file_atomically(out_dir / "case.toml", case_text);
  write_file_atomically(out_dir / "mpm_case.toml", mpm_text);

  CentrifugeSummary summary;
  summary.title = s.title;
  const double D = s.pile_diameter;
  const double factor = mpm_full_body_factor(mpm_case.geometry);
  PileRecorder recorder(s, factor);
  std::vector<mpm::Vec2> reference_position;  // after the K0 phase
  MpmRunHooks hooks;
  hooks.after_step = [&](const mpm::Solver& solver, const MpmPhase& phase, double dt) {
    recorder.after_step(solver, phase, dt);
  };
  summary.min_radius_mm = kNaN;
  hooks.phase_end = [&](const mpm::Solver& solver, const MpmPhase& phase) {
    recorder.phase_end(solver, phase);
    // No particle passes through the pile, none crosses the axis.
    std::size_t inside = 0;
    double min_radius = std::numeric_limits<double>::infinity();
    const double cell = D / s.cells_per_D;
    for (const mpm::Vec2& x : solver.particles().position) {
      const double distance = solver.rigid_body(0).signed_distance(x);
      if (distance < -cell) ++inside;
      summary.max_penetration_cells = std::max(summary.max_penetration_cells, -distance / cell);
      min_radius = std::min(min_radius, x.x());
    }
    summary.particles_in_pile = std::max(summary.particles_in_pile, inside);
    if (!(1e3 * min_radius >= summary.min_radius_mm)) summary.min_radius_mm = 1e3 * min_radius;
    if (phase.name == "initial-stress") {
      initial_stress_check(s, solver, summary);
      summary.particles = solver.particles().size();
      reference_position = solver.particles().position;
      if (progress != nullptr)
        *progress << fmt::format(
            "centrifuge: K0 stress: max |σv − ρNgz| / ρNgH = {:.2f} %, mean σv / ρNgz = {:.4f}\n",
            100.0 * summary.initial_stress_error, summary.initial_stress_ratio);
      return;
    }
    // The fields at the snapshot depths and the ends of installation and load test.
    if (!is_installation(phase.name) && phase.name != "load-test") return;
    const std::string stem = "fields_" + phase.name;
    write_file_atomically(out_dir / (stem + ".csv"), fields_csv(solver, s.sand_height()));
    std::vector<int> material_index(solver.materials().size());
    for (std::size_t k = 0; k < material_index.size(); ++k) material_index[k] = static_cast<int>(k);
    write_vtu(out_dir / (stem + ".vtu"),
              mpm_particle_cloud(solver, reference_position, material_index));
    summary.field_files.push_back(stem + ".csv");
  };

  const MpmRunSummary run = run_mpm_case(mpm_case, out_dir / "mpm", progress, {}, hooks);
  summary.steps = run.steps;
  summary.wall_seconds = run.wall_seconds;
  const std::vector<PileRow>& rows = recorder.rows();
  write_file_atomically(out_dir / "pile.csv", pile_csv(rows, D));

  // The figures of the summary.
  summary.installation_head_force = summary.installation_tip_depth_D = kNaN;
  summary.peak_tip_stress_MPa = summary.peak_tip_stress_depth_D = kNaN;
  summary.relaxation_travel_mm = summary.capacity = summary.load_test_displacement_mm = kNaN;
  summary.equilibrium_error = summary.equilibrium_error_1D = summary.equilibrium_closure = kNaN;
  summary.max_kinetic_to_work = kNaN;
  const double tip_area = std::numbers::pi * 0.25 * D * D;
  const double cell = D / s.cells_per_D;
  double end_displacement = 0.0;
  for (const PileRow& r : rows)
    if (is_installation(r.phase)) end_displacement = r.displacement;
  double sum = 0.0, weight = 0.0, last_displacement = -1.0;
  for (const PileRow& r : rows) {
    if (is_installation(r.phase)) {
      const double stress = r.tip / tip_area / 1e6;
      if (!(stress <= summary.peak_tip_stress_MPa)) {
        summary.peak_tip_stress_MPa = stress;
        summary.peak_tip_stress_depth_D = r.tip_depth / D;
      }
      const double travel = r.displacement - std::max(last_displacement, 0.0);
      if (r.displacement >= end_displacement - cell - 1e-12 && travel > 0.0) {
        sum += r.head * travel;
        weight += travel;
      }
      if (r.pile_work > 0.0 && r.displacement >= D)
        summary.max_kinetic_to_work =
            std::max(std::isfinite(summary.max_kinetic_to_work) ? summary.max_kinetic_to_work : 0.0,
                     r.kinetic / r.pile_work);
      last_displacement = r.displacement;
      summary.installation_tip_depth_D = r.tip_depth / D;
    }
    if (r.phase == "relaxation") summary.relaxation_travel_mm = -1e3 * r.phase_displacement;
    if (r.phase == "load-test") {
      summary.capacity = r.head;
      summary.load_test_displacement_mm = 1e3 * r.phase_displacement;
    }
  }
  if (weight > 0.0) summary.installation_head_force = sum / weight;
  if (std::isfinite(summary.installation_head_force)) {
    const auto residual = [](const PileRow& r) { return r.equilibrium_residual(); };
    const double threshold = 0.5 * summary.installation_head_force;
    summary.equilibrium_error = max_window_ratio(rows, cell, threshold, residual);
    summary.equilibrium_error_1D = max_window_ratio(rows, D, threshold, residual);
    summary.equilibrium_closure = max_window_ratio(
        rows, cell, threshold, [](const PileRow& r) { return r.force_book_closure(); });
  }

  std::vector<FigureSpec> figures = run_figures(s);
  for (const FigureSpec& f : figures) summary.figures.push_back(f.file);
  write_file_atomically(out_dir / "plot_figures.py", plot_script_text());
  write_file_atomically(out_dir / "figures.json", figures_json(figures));
  if (options.plots && !figures.empty()) {
    const PlotOutcome plots =
        draw_figures(out_dir / "plot_figures.py", out_dir / "figures.json", options.python);
    if (!plots.plotted) summary.plot_problem = plots.problem;
  }
  write_file_atomically(out_dir / "summary.json", centrifuge_summary_json(summary));
  write_file_atomically(out_dir / "summary.csv", centrifuge_summary_csv(summary));
  write_file_atomically(out_dir / "summary.md", summary_markdown(s, summary));
  return summary;
}

}  // namespace pilempm
