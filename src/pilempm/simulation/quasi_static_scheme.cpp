// The quasi-static analysis as a Scheme: see quasi_static_scheme.hpp.
#include "pilempm/simulation/quasi_static_scheme.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "pilempm/core/error.hpp"
#include "pilempm/simulation/case_assembly.hpp"
#include "pilempm/simulation/tractions.hpp"

namespace pilempm::simulation {

void LoadStepRecord::add(const mpm::quasi_static::LoadStepResult& step, double seconds) {
  ++solves;
  iterations += step.iterations;
  cuts += step.cuts;
  accepted += step.accepted;
  largest_accepted_residual = std::max(largest_accepted_residual, step.largest_accepted_residual);
  stabilised += step.stabilised;
  if (step.rescued) ++rescued;
  largest_stabilisation_share =
      std::max(largest_stabilisation_share, step.largest_stabilisation_share);
  most_iterations = std::max(most_iterations, step.iterations);
  unknowns = step.unknowns;
  material_seconds += step.seconds_material;
  assembly_seconds += step.seconds_assembly;
  factorisation_seconds += step.seconds_factorisation;
  wall_seconds += seconds;
}

QuasiStaticScheme::QuasiStaticScheme(const MpmCase& mpm_case)
    : case_(mpm_case), solver_(make_quasi_static_solver(mpm_case)) {
  if (!mpm_case.tractions.empty())
    traction_forces_ = mpm_traction_forces(mpm_case, solver_.particles());
}

double QuasiStaticScheme::displacement_step() const {
  const double phase_step = case_.phases.at(phase_).displacement_step;
  if (phase_step > 0.0) return phase_step;
  if (case_.displacement_step > 0.0) return case_.displacement_step;
  double cell = std::numeric_limits<double>::infinity();
  for (const std::vector<double>* nodes : {&case_.x_nodes, &case_.y_nodes})
    for (std::size_t i = 1; i < nodes->size(); ++i)
      cell = std::min(cell, (*nodes)[i] - (*nodes)[i - 1]);
  return 0.1 * cell;
}

std::string QuasiStaticScheme::begin_phase(std::size_t index) {
  phase_ = index;
  control_.reset();
  control_.emplace(case_, index, solver_, /*average_forces=*/false);
  control_->start(traction_forces_);
  return control_->stop_reason();
}

double QuasiStaticScheme::step_length() {
  const double end = phase_end_time();
  const double speed = control_ ? control_->body_speed() : 0.0;
  // A phase in which nothing moves needs no more steps than its output times.
  return speed > 0.0 ? displacement_step() / speed : std::max(end - solver_.time(), 0.0);
}

namespace {

// The state a load step starts from, to go back to when a force rule is bisected.
struct SavedState {
  mpm::Particles particles;
  std::vector<mpm::RigidBody> bodies;
  mpm::SolverRunState run;
};

SavedState save(const mpm::MpmState& state) {
  SavedState saved{state.particles(), {}, state.run_state()};
  for (int b = 0; b < state.rigid_body_count(); ++b) saved.bodies.push_back(state.rigid_body(b));
  return saved;
}

void restore(mpm::MpmState& state, const SavedState& saved) {
  state.restore_run_state(saved.run);
  for (int b = 0; b < state.rigid_body_count(); ++b)
    state.rigid_body(b) = saved.bodies[static_cast<std::size_t>(b)];
  state.particles() = saved.particles;
}

bool is_force_rule(const MpmStopRule& rule) {
  return rule.quantity == MpmStopQuantity::force_below ||
         rule.quantity == MpmStopQuantity::force_above;
}

// A load step in which a force rule is first met is re-solved at shorter lengths until the
// force lies within 2^-12 = 2.4e-4 of the step's change of force of the rule's value (on the side
// that meets it), or the bracket of the crossing is 2^-12 of the step wide, in at most this many
// solves.
constexpr int kForceSolves = 12;
constexpr double kForceResolution = 1.0 / 4096.0;

}  // namespace

void QuasiStaticScheme::solve_load_step(double duration) {
  const MpmPhase& phase = case_.phases.at(phase_);
  mpm::quasi_static::LoadStep load;
  load.duration = duration;
  load.gravity_multiplier = phase.gravity_multiplier;
  load.traction_multiplier = traction_forces_.empty() ? 0.0 : 1.0;  // the phase's loads are set
  for (int b = 0; b < solver_.rigid_body_count(); ++b)
    load.body_displacement.push_back(solver_.rigid_body(b).velocity() * duration);
  const auto start = std::chrono::steady_clock::now();
  last_step_ = solver_.solve_step(load);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  last_advance_.add(last_step_, seconds);
  total_.add(last_step_, seconds);
  if (!last_step_.converged)
    throw Error(fmt::format(
        "quasi-static load step {} (from t = {:.6g} s to {:.6g} s): {}; the state is that of the "
        "last converged step. A case driven by inertia needs [solver] analysis = \"explicit\"; "
        "else try a smaller displacement_step_m or more max_cuts",
        solver_.steps() + 1, solver_.time(), solver_.time() + duration, last_step_.message));
  max_penetration_ = std::max(max_penetration_, solver_.max_penetration());
  control_->record_step(duration);
}

Advance QuasiStaticScheme::advance(double target) {
  if (!control_) throw Error("QuasiStaticScheme::advance: no phase begun");
  const MpmPhase& phase = case_.phases.at(phase_);
  double step = step_length();
  // A step that would end within round-off of the target ends on it (no sliver of a step after).
  if (!(step > 0.0) || target - time() <= step * (1.0 + 1e-9)) step = target - time();
  last_advance_ = LoadStepRecord{};
  const MpmStepPlan plan = control_->plan_step(target, step);
  const double duration = plan.end - solver_.time();
  const bool force_rules =
      std::any_of(phase.stop_rules.begin(), phase.stop_rules.end(), is_force_rule);
  std::optional<SavedState> start;
  std::vector<double> start_margin(phase.stop_rules.size(), 0.0);
  if (force_rules) {
    start = save(solver_);
    for (std::size_t k = 0; k < phase.stop_rules.size(); ++k)
      if (is_force_rule(phase.stop_rules[k])) start_margin[k] = control_->force_margin(int(k));
  }
  solve_load_step(duration);
  Advance advance;
  advance.dt = duration;
  advance.at_target = !plan.own_step && plan.landing_rule < 0;
  const int rule = control_->met_rule(plan.landing_rule);
  if (rule >= 0 && start && is_force_rule(phase.stop_rules[static_cast<std::size_t>(rule)]) &&
      plan.landing_rule < 0) {
    // Met within this step, not at its start (else the phase would have ended): find where
    // the force crosses the rule's value along the step's length by the Illinois variant of
    // regula falsi (Dowell & Jarratt 1971, BIT 11), which keeps the crossing bracketed and
    // converges superlinearly; the force of a load step's end is close to linear in its length,
    // so a few solves replace the bisection's thirteen.
    double met = 1.0, not_met = 0.0;
    double met_margin = control_->force_margin(rule);  // negative: met
    // The secant's values: the margins, with the Illinois halvings. A rule already met at the
    // step's start (in a phase's first step, before any force was compared) is bisected.
    double met_value = met_margin, not_met_value = start_margin[static_cast<std::size_t>(rule)];
    const bool secant = not_met_value > 0.0;
    const double resolution = secant ? kForceResolution * (not_met_value - met_value) : 0.0;
    bool at_met = true;  // whether the solver's state is the one at `met`
    int replaced = 0;    // the end the last solve replaced: +1 met, -1 not met
    for (int k = 0; k < kForceSolves && -met_margin > resolution; ++k) {
      if (met - not_met <= kForceResolution) break;
      double length = 0.5 * (met + not_met);
      if (secant) {  // within the bracket, by at least a small share of it from either end
        const double inset = 0.01 * (met - not_met);
        length =
            std::clamp((not_met * met_value - met * not_met_value) / (met_value - not_met_value),
                       not_met + inset, met - inset);
      }
      restore(solver_, *start);
      solve_load_step(length * duration);
      const double f = control_->force_margin(rule);
      at_met = f < 0.0;
      if (at_met) {
        met = length;
        met_margin = met_value = f;
        if (replaced == 1) not_met_value *= 0.5;
        replaced = 1;
      } else {
        not_met = length;
        not_met_value = f;
        if (replaced == -1) met_value *= 0.5;
        replaced = -1;
      }
    }
    if (!at_met) {
      restore(solver_, *start);
      solve_load_step(met * duration);
    }
    advance.dt = met * duration;
    // Short of the target unless the crossing lies at the step's very end.
    advance.at_target = advance.at_target && met == 1.0;
  }
  advance.stop_reason = control_->stop_reason(plan.landing_rule);
  return advance;
}

std::string QuasiStaticScheme::step_report() const {
  return fmt::format(
      "{} it, {} cuts{}{}{}, penetration {:.2g} m", last_step_.iterations, last_step_.cuts,
      last_step_.rescued > 0 ? ", finished with the low-stress stabilisation" : "",
      last_step_.accepted > 0
          ? fmt::format(", accepted at ||R|| = {:.1e} F_ref", last_step_.largest_accepted_residual)
          : std::string(),
      last_step_.stabilised > 0
          ? fmt::format(", {} stabilised (share {:.2g})", last_step_.stabilised,
                        last_step_.largest_stabilisation_share)
          : std::string(),
      solver_.max_penetration());
}

PhaseProgress QuasiStaticScheme::phase_progress() const {
  return control_ ? control_->progress() : PhaseProgress{};
}

double QuasiStaticScheme::phase_end_time() const {
  return control_ ? control_->end_time() : solver_.time();
}

}  // namespace pilempm::simulation
