#include "pilempm/study/centrifuge_run.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <tuple>

#include "pilempm/constitutive/material_state.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/core/number_text.hpp"
#include "pilempm/io/centrifuge_case.hpp"
#include "pilempm/io/mpm_case.hpp"
#include "pilempm/io/mpm_case_writer.hpp"
#include "pilempm/io/mpm_checkpoint.hpp"
#include "pilempm/io/mpm_output.hpp"
#include "pilempm/io/output/atomic_file.hpp"
#include "pilempm/io/output/format.hpp"
#include "pilempm/io/output/json_writer.hpp"
#include "pilempm/io/vtu_writer.hpp"
#include "pilempm/scenario/centrifuge/run_checks.hpp"
#include "pilempm/simulation/body_force_means.hpp"
#include "pilempm/simulation/phase_control.hpp"
#include "pilempm/simulation/run_loop.hpp"
#include "pilempm/study/figures.hpp"
#include "pilempm/study/plotting.hpp"
#include "pilempm/study/quick_centrifuge_case.hpp"

namespace pilempm {

using namespace simulation;
using namespace scenario;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The numbers of a line of a checkpoint's centrifuge record, separated by tabs, after a first
// field `tag` where the line has one ("checks"); strtod reads "nan" and "inf" too. Empty when
// a field is not a number.
std::vector<double> tab_separated_numbers(const std::string& line, const std::string& tag) {
  std::vector<double> numbers;
  std::istringstream fields(line);
  bool first = true;
  for (std::string field; std::getline(fields, field, '\t'); first = false) {
    if (first && field == tag) continue;
    const std::optional<double> value = whole_number(field);
    if (!value) return {};
    numbers.push_back(*value);
  }
  return numbers;
}

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
std::string fields_csv(const mpm::MpmState& solver, double surface) {
  const std::vector<double> igs_size = mpm_igs_sizes(solver);
  const mpm::Particles& particles = solver.particles();
  std::string text =
      "# the sand's particles: r_mm from the axis, depth_mm below the initial sand surface, "
      "p and q in kPa (compression positive), igs_rho = ||delta|| / R of the intergranular "
      "strain (0 for sand without one), half_r_mm and half_depth_mm the half-lengths of the "
      "particle's domain\n"
      "r_mm,depth_mm,void_ratio,p_kPa,q_kPa,igs_rho,half_r_mm,half_depth_mm\n";
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const MaterialState& state = particles.state[p];
    const double R = igs_size[static_cast<std::size_t>(particles.material[p])];
    const double rho =
        R > 0.0 ? std::min(1.0, Vec6(Hypoplastic::intergranular_strain(state)).norm() / R) : 0.0;
    text +=
        csv_row({csv_number(1e3 * particles.position[p].x(), 6),
                 csv_number(1e3 * (surface - particles.position[p].y()), 6),
                 csv_number(state.void_ratio, 6), csv_number(mean_stress(state.stress) / 1e3, 6),
                 csv_number(deviator_stress(state.stress) / 1e3, 6), csv_number(rho, 4),
                 csv_number(1e3 * particles.half_size[p].x(), 6),
                 csv_number(1e3 * particles.half_size[p].y(), 6)});
  }
  return text;
}

// The pile's half-section (r >= 0) at the solver's time, cut at the grid's top, as CSV in the
// coordinates of fields_csv.
std::string pile_outline_csv(const mpm::MpmState& solver, double surface) {
  std::string text =
      "# the pile's half-section: its outline's corners, r_mm from the axis, depth_mm below the "
      "initial sand surface (cut at the top of the grid)\nr_mm,depth_mm\n";
  for (const mpm::Vec2& v :
       mpm_body_outline(solver.rigid_body(0), solver.grid().y_axis().end(), true))
    text += csv_row({csv_number(1e3 * v.x(), 6), csv_number(1e3 * (surface - v.y()), 6)});
  return text;
}

// The fields after the initial stress (the reference positions, and the K0 line on the progress
// stream), at the snapshot depths and at the ends of installation and load test.
class FieldWriter final : public RunObserver {
 public:
  FieldWriter(const CentrifugeScenario& s, const std::filesystem::path& out_dir,
              std::ostream* progress, CentrifugeSummary& summary)
      : s_(s), out_dir_(out_dir), progress_(progress), summary_(summary) {}

  void phase_end(const Scheme& scheme, const MpmPhase& phase) override {
    const mpm::MpmState& solver = scheme.state();
    if (phase.role == MpmPhaseRole::initial_stress) {
      reference_position_ = solver.particles().position;
      if (progress_ != nullptr)
        *progress_ << fmt::format(
            "centrifuge: K0 stress: max |σv − ρNgz| / ρNgH = {:.2f} %, mean σv / ρNgz = {:.4f}\n",
            100.0 * summary_.initial_stress_error, summary_.initial_stress_ratio);
      return;
    }
    if (phase.role != MpmPhaseRole::installation && phase.role != MpmPhaseRole::load_test) return;
    const std::string stem = "fields_" + phase.name;
    write_file_atomically(out_dir_ / (stem + ".csv"), fields_csv(solver, s_.sand_height()));
    write_file_atomically(out_dir_ / (stem + "_pile.csv"),
                          pile_outline_csv(solver, s_.sand_height()));
    std::vector<int> material_index(solver.materials().size());
    for (std::size_t k = 0; k < material_index.size(); ++k) material_index[k] = static_cast<int>(k);
    write_vtu(out_dir_ / (stem + ".vtu"),
              mpm_particle_cloud(solver, reference_position_, material_index));
    summary_.field_files.push_back(stem + ".csv");
  }

  // The checkpoint's record: the field files so far, then the reference positions.
  std::string saved() const {
    std::string text = fmt::format("{}\n", summary_.field_files.size());
    for (const std::string& file : summary_.field_files) text += file + "\n";
    for (const mpm::Vec2& x : reference_position_)
      text += fmt::format("{:.17g}\t{:.17g}\n", x.x(), x.y());
    return text;
  }
  // The files of the run that wrote the checkpoint (`from`, its folder) copied here.
  void restore(const std::string& saved, const std::filesystem::path& from) {
    std::istringstream lines(saved);
    std::size_t count = 0;
    lines >> count;
    lines.ignore();
    std::vector<std::string> files(count);
    for (std::string& file : files) std::getline(lines, file);
    std::vector<mpm::Vec2> reference;
    for (std::string line; std::getline(lines, line);) {
      const std::vector<double> x = tab_separated_numbers(line, "field reference positions");
      if (x.size() != 2) throw Error("the field files of a checkpoint cannot be read");
      reference.emplace_back(x[0], x[1]);
    }
    const bool elsewhere = !std::filesystem::equivalent(from, out_dir_);
    for (const std::string& csv : files) {
      const std::string stem = std::filesystem::path(csv).stem().string();
      if (elsewhere)
        for (const std::string& file : {csv, stem + "_pile.csv", stem + ".vtu"}) {
          std::ifstream in(from / file, std::ios::binary);
          std::ostringstream bytes;
          bytes << in.rdbuf();
          if (!in)
            throw Error(
                fmt::format("cannot read {}, a field file of the run that wrote the "
                            "checkpoint",
                            (from / file).string()));
          write_file_atomically(out_dir_ / file, bytes.str());
        }
      summary_.field_files.push_back(csv);
    }
    reference_position_ = std::move(reference);
  }

 private:
  const CentrifugeScenario& s_;
  std::filesystem::path out_dir_;
  std::ostream* progress_;
  CentrifugeSummary& summary_;
  std::vector<mpm::Vec2> reference_position_;  // after the K0 phase
};

// The name of a centrifuge run's record in its checkpoints.
constexpr const char* kCentrifugeRecord = "centrifuge run";

// The MPM case's text with its phases before `phases` only and no title: what a checkpoint
// after `phases` phases must share with the case that continues it.
std::string case_before(const MpmCase& mpm_case, std::size_t phases) {
  MpmCase c = mpm_case;
  c.title.clear();
  c.phases.resize(std::min(phases, c.phases.size()));
  return mpm_case_text(c);
}

std::string first_difference(const std::string& a, const std::string& b) {
  std::istringstream x(a), y(b);
  std::string l, m;
  for (int line = 1;; ++line) {
    const bool more_x = static_cast<bool>(std::getline(x, l));
    const bool more_y = static_cast<bool>(std::getline(y, m));
    if (!more_x && !more_y) return "no line differs";
    if (!more_x || !more_y || l != m)
      return fmt::format("line {} of its MPM case is \"{}\", of this one \"{}\"", line,
                         more_x ? l : "(none)", more_y ? m : "(none)");
  }
}

// A checkpoint's centrifuge record, read: the checks so far (at_phase_end, then the six numbers
// of CentrifugeRunState::save) and the parts "case", "pile" and "fields".
struct CentrifugeRecord {
  std::vector<double> checks;
  std::map<std::string, std::string> parts;
};

// The record `saved` of the checkpoint `file` (after `phases_done` phases), read and checked
// against the MPM case `mpm_case` that is to continue it: InputError naming the checkpoint when
// it has none (a checkpoint of `pilempm mpm run`), cannot be read, was taken in the middle of a
// phase, or was written by a case that differs before it.
CentrifugeRecord checked_centrifuge_record(const MpmCase& mpm_case, const std::string& saved,
                                           std::size_t phases_done,
                                           const std::filesystem::path& file) {
  const auto refused = [&](const std::string& why) {
    return InputError(file.string(), 0, "--restart", file.string(), why);
  };
  if (saved.empty())
    throw refused(
        "was not written by a centrifuge run (`pilempm centrifuge run`): it holds no "
        "centrifuge record (the pile recorded so far)");
  if (phases_done < 1 || phases_done >= mpm_case.phases.size())
    throw refused(
        fmt::format("holds the state after {} phase(s), and the case has {}: nothing "
                    "left to run",
                    phases_done, mpm_case.phases.size()));
  CentrifugeRecord record;
  std::istringstream in(saved);
  std::string checks;
  std::getline(in, checks);
  record.checks = tab_separated_numbers(checks, "checks");
  bool readable = record.checks.size() == 7;
  for (std::string name; readable && in >> name;) {
    std::size_t size = 0;
    in >> size;
    in.ignore();
    std::string part(size, '\0');
    in.read(part.data(), static_cast<std::streamsize>(size));
    readable = static_cast<std::size_t>(in.gcount()) == size;
    record.parts[name] = std::move(part);
  }
  if (!readable || record.parts.size() != 3 || record.parts.count("case") == 0)
    throw refused("its centrifuge record cannot be read");
  if (record.checks[0] != 1.0)
    throw refused(fmt::format(
        "holds the last converged state of a phase that failed (\"{}\"), in its middle: a "
        "centrifuge run continues from the end of a phase (checkpoint_NN_<phase>.h5)",
        mpm_case.phases.at(phases_done).name));
  const std::string mine = case_before(mpm_case, phases_done);
  if (record.parts["case"] != mine)
    throw refused(fmt::format(
        "was written by a run whose MPM case up to its phase {} (\"{}\") differs from this "
        "case's: {} (a restart continues the same case; only the phases after the "
        "checkpoint may differ)",
        phases_done, mpm_case.phases.at(phases_done - 1).name,
        first_difference(record.parts["case"], mine)));
  return record;
}

// What a centrifuge run keeps in each checkpoint besides the MPM state, so that a run restarted
// from it (CentrifugeRunOptions::restart) writes what the whole run would have: the MPM case of
// the phases done (a restart must continue the same case), the pile's rows, the checks so far
// and the field files.
class CentrifugeRunState final : public CheckpointedState {
 public:
  CentrifugeRunState(const MpmCase& mpm_case, PileRecorder& recorder, FieldWriter& fields,
                     CentrifugeSummary& summary)
      : case_(mpm_case), recorder_(recorder), fields_(fields), summary_(summary) {}

  std::string record_name() const override { return kCentrifugeRecord; }

  std::string save(std::size_t phases_done, bool at_phase_end) const override {
    std::string text = fmt::format(
        "checks\t{}\t{:.17g}\t{:.17g}\t{}\t{}\t{:.17g}\t{:.17g}\n", at_phase_end ? 1 : 0,
        summary_.initial_stress_error, summary_.initial_stress_ratio, summary_.particles,
        summary_.particles_in_pile, summary_.max_penetration_cells, summary_.min_radius_mm);
    const std::string done = case_before(case_, phases_done);
    const std::string pile = recorder_.saved();
    const std::string fields = fields_.saved();
    for (const auto& [name, part] :
         {std::pair{"case", &done}, std::pair{"pile", &pile}, std::pair{"fields", &fields}})
      text += fmt::format("{}\t{}\n{}", name, part->size(), *part);
    return text;
  }

  void restore(const std::string& saved, std::size_t phases_done,
               const std::filesystem::path& file) override {
    CentrifugeRecord record = checked_centrifuge_record(case_, saved, phases_done, file);
    const std::vector<double>& numbers = record.checks;
    summary_.initial_stress_error = numbers[1];
    summary_.initial_stress_ratio = numbers[2];
    summary_.particles = static_cast<std::size_t>(numbers[3]);
    summary_.particles_in_pile = static_cast<std::size_t>(numbers[4]);
    summary_.max_penetration_cells = numbers[5];
    summary_.min_radius_mm = numbers[6];
    recorder_.restore(record.parts["pile"]);
    // The run folder that wrote the checkpoint: DIR/mpm/checkpoint_*.h5.
    fields_.restore(record.parts["fields"],
                    std::filesystem::absolute(file).parent_path().parent_path());
  }

 private:
  const MpmCase& case_;
  PileRecorder& recorder_;
  FieldWriter& fields_;
  CentrifugeSummary& summary_;
};

// The verdict of the run's own checks: "**Checks: PASS**" or "**FAILED**" with each failed
// check, then every check.
std::string checks_markdown(const std::vector<CentrifugeCheck>& checks) {
  const std::vector<CentrifugeCheck> failed = failed_checks(checks);
  std::string md = failed.empty()
                       ? "**Checks: PASS** (docs/verification.md §8 gives the limits).\n\n"
                       : fmt::format(
                             "**FAILED: {} of the run's own checks failed**; the results below "
                             "are kept but do not hold (docs/verification.md §8 gives the "
                             "limits).\n\n",
                             failed.size());
  for (const CentrifugeCheck& c : checks)
    md +=
        fmt::format("- {}{}\n", c.passed ? (c.applies ? "pass: " : "") : "**FAILED**: ", c.text());
  return md + "\n";
}

std::string summary_markdown(const CentrifugeScenario& s, const CentrifugeSummary& r) {
  auto value = [](double v, const char* format) { return shown_number(v, format); };
  std::string md = fmt::format("# {}\n\n", r.title);
  const std::string sand =
      scenario_sand_is_hypoplastic(s)
          ? fmt::format("e0 = {:g} ({}), set \"{}\" with {}", s.e0, s.e0_at,
                        s.installation_material, s.igs)
          : fmt::format("e0 = {:g}, material \"{}\" ({})", s.e0, s.installation_material,
                        scenario_material(s, s.installation_material).model);
  md += fmt::format(
      "D = {:g} mm at {:g} g, container R = {:g} D, sand H = {:g} D, {}, {} analysis, pile "
      "wished in place at {:g} D, installed {:g} D.\n\n",
      1e3 * s.pile_diameter, s.g_level, s.container_radius_D, s.sand_height_D, sand,
      to_string(s.analysis), s.wished_in_place_D, s.installation_D);
  if (!r.restarted_from.empty())
    md += fmt::format(
        "Continued from the checkpoint `{}`: the phases up to it are that run's (the same MPM "
        "case), the wall time is this run's.\n\n",
        r.restarted_from);
  md += checks_markdown(centrifuge_checks(r));
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
  md += fmt::format(
      "| head force's scatter about a quadratic over a D of travel, over its mean: the last D; "
      "the largest D (from) | {} %; {} % ({} D) |\n",
      value(100.0 * r.scatter_last_D, "{:.2f}"), value(100.0 * r.largest_scatter, "{:.2f}"),
      value(r.largest_scatter_from_D, "{:.3g}"));
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
  const std::vector<ScenarioPhase> phases = scenario_phases(s);
  std::string last_installation;  // labels the forces, once for the split installation
  for (const ScenarioPhase& phase : phases)
    if (phase.role == MpmPhaseRole::installation) last_installation = phase.name;
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
      for (const ScenarioPhase& phase : phases)
        if (phase.role == MpmPhaseRole::installation)
          force.series.push_back(curve("pile.csv", {{"phase", phase.name}}, "pile_displacement_mm",
                                       column, phase.name == last_installation ? label : "",
                                       SeriesStyle{colour, "-", "", 1.2, 0}));
    f.panels.push_back(force);
    PanelSpec tip;
    tip.title = "tip stress against tip depth";
    tip.x.label = "mean normal stress on the tip [MPa]";
    tip.y.label = "tip depth [D]";
    for (const ScenarioPhase& phase : phases)
      if (phase.role == MpmPhaseRole::installation)
        tip.series.push_back(curve("pile.csv", {{"phase", phase.name}}, "tip_stress_MPa",
                                   "tip_depth_D", "", SeriesStyle{"C3", "-", "", 1.2, 0}));
    tip.legend = "none";
    f.panels.push_back(tip);
    figures.push_back(f);
  }
  for (const ScenarioPhase& phase : phases) {
    if (phase.role != MpmPhaseRole::load_test) continue;
    FigureSpec f;
    f.file = "load_test.png";
    f.title = s.title + ": static load test";
    PanelSpec panel;
    panel.x.label = "pile displacement in the load test [mm]";
    panel.y.label = "force [N]";
    for (auto [column, label, colour] : {std::tuple{"head_force_N", "head", "C0"},
                                         {"tip_force_N", "tip", "C1"},
                                         {"shaft_force_N", "shaft", "C2"}})
      panel.series.push_back(curve("pile.csv", {{"phase", phase.name}}, "phase_displacement_mm",
                                   column, label, SeriesStyle{colour, "-", "", 1.4, 0}));
    f.panels.push_back(panel);
    figures.push_back(f);
  }
  for (const ScenarioPhase& phase : phases)
    if (phase.role == MpmPhaseRole::installation || phase.role == MpmPhaseRole::load_test)
      figures.push_back(field_figure(s, phase.name));
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
  const std::string pile_csv =
      (csv.ends_with(".csv") ? csv.substr(0, csv.size() - 4) : csv) + "_pile.csv";
  // Fixed scales, so that runs can be compared: e from dense to loose, stresses logarithmic
  // from the overburden near the surface to the tip's MPa. The zone around the pile: 5 D
  // around the axis, from 3 D above the tip (at most half a D above the sand) to 5 D below.
  // The IGS panel for hypoplastic sand only.
  const bool hypoplastic = scenario_sand_is_hypoplastic(s);
  if (!hypoplastic) f.cols = 3;
  for (auto [column, label, map, low, high, log] :
       {std::tuple{"void_ratio", "void ratio [-]", "viridis", 0.55, 0.95, false},
        {"p_kPa", "p [kPa]", "magma", 5.0, 5000.0, true},
        {"q_kPa", "q [kPa]", "magma", 5.0, 5000.0, true},
        {"igs_rho", "IGS rho [-]", "cividis", 0.0, 1.0, false}}) {
    if (!hypoplastic && std::string_view(column) == "igs_rho") continue;
    PanelSpec panel;
    panel.x.label = "r [mm]";
    panel.y.label = "depth [mm]";
    panel.x.limits = std::pair{0.0, std::min(5.0, s.container_radius_D) * mm};
    panel.y.limits = std::pair{std::max(-0.5, deepest - 3.0) * mm, (deepest + 5.0) * mm};
    panel.y.invert = true;
    panel.legend = "none";
    SeriesSpec series = curve(csv, {}, "r_mm", "depth_mm", "", SeriesStyle{"", "", "", 0.0, 3.0});
    series.color_by = column;
    series.color_label = label;
    series.colormap = map;
    series.color_limits = std::pair{low, high};
    series.color_log = log;
    series.half_x = "half_r_mm";
    series.half_y = "half_depth_mm";
    panel.series.push_back(series);
    SeriesSpec pile =
        curve(pile_csv, {}, "r_mm", "depth_mm", "", SeriesStyle{"black", "-", "", 0.8, 0.0});
    pile.fill = "0.6";
    panel.series.push_back(pile);
    f.panels.push_back(panel);
  }
  return f;
}

void check_centrifuge_restart(const CentrifugeScenario& s,
                              const std::filesystem::path& checkpoint) {
  const MpmCheckpointInfo info = read_mpm_checkpoint_info(checkpoint);
  const auto record = info.records.find(kCentrifugeRecord);
  (void)checked_centrifuge_record(centrifuge_case(s, ""),
                                  record == info.records.end() ? std::string() : record->second,
                                  static_cast<std::size_t>(info.next_phase), checkpoint);
}

std::filesystem::path centrifuge_installation_checkpoint(const CentrifugeScenario& s) {
  const MpmCase c = centrifuge_case(s, "");
  std::filesystem::path file;
  for (std::size_t k = 0; k < c.phases.size(); ++k)
    if (c.phases[k].role == MpmPhaseRole::installation && c.phases[k].checkpoint)
      file = std::filesystem::path("mpm") / mpm_checkpoint_name(k + 1, c.phases[k].name);
  return file;
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
          {"scatter_last_D", r.scatter_last_D},
          {"largest_scatter", r.largest_scatter},
          {"largest_scatter_from_D", r.largest_scatter_from_D},
          {"particles_in_pile", static_cast<double>(r.particles_in_pile)},
          {"max_penetration_cells", r.max_penetration_cells},
          {"min_radius_mm", r.min_radius_mm},
          {"checks_failed", static_cast<double>(failed_checks(centrifuge_checks(r)).size())}};
}

}  // namespace

std::string centrifuge_summary_json(const CentrifugeSummary& r) {
  std::string json = "{\n  \"title\": " + json_quote(r.title);
  const std::vector<CentrifugeCheck> failed = failed_checks(centrifuge_checks(r));
  json += fmt::format(",\n  \"checks\": {}", json_quote(failed.empty() ? "PASS" : "FAILED"));
  json += ",\n  \"failed_checks\": [";
  for (std::size_t k = 0; k < failed.size(); ++k)
    json += (k == 0 ? "" : ", ") + json_quote(failed[k].text());
  json += "]";
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
  const MpmCase mpm_case = centrifuge_case(s, (out_dir / "mpm_case.toml").string());
  const std::string mpm_text = centrifuge_mpm_case_text(mpm_case);
  prepare_output_directory(out_dir);
  if (!case_text.empty()) write_file_atomically(out_dir / "case.toml", case_text);
  write_file_atomically(out_dir / "mpm_case.toml", mpm_text);

  CentrifugeSummary summary;
  summary.title = s.title;
  const double D = s.pile_diameter;
  PileRecorder recorder(s, mpm_full_body_factor(mpm_case.geometry));
  CentrifugeChecks checks(s, summary);
  FieldWriter fields(s, out_dir, progress, summary);
  CentrifugeRunState state(mpm_case, recorder, fields, summary);
  MpmRunHooks hooks;
  hooks.observers = {&recorder, &checks, &fields};
  hooks.checkpointed = {&state};
  hooks.progress_on_terminal = options.progress_on_terminal;
  if (!options.restart.empty() && progress != nullptr)
    *progress << fmt::format("centrifuge: continues from {}\n", options.restart.string());
  const MpmRunSummary run =
      run_mpm_case(mpm_case, out_dir / "mpm", progress, options.restart, hooks);
  summary.restarted_from = options.restart.string();
  summary.steps = run.steps;
  summary.wall_seconds = run.wall_seconds;
  const std::vector<PileRow>& rows = recorder.rows();
  write_file_atomically(out_dir / "pile.csv", pile_csv(rows, D));
  summarise_pile(s, rows, summary);

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
