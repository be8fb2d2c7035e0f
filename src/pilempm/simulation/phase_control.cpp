// Phase control of MPM runs: see phase_control.hpp.
#include "pilempm/simulation/phase_control.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "pilempm/core/tensor.hpp"
#include "pilempm/simulation/case_assembly.hpp"

namespace pilempm::simulation {

namespace {

// How far `force` is from meeting a force rule [N], negative where it is met.
double rule_margin(const MpmStopRule& rule, const mpm::Vec2& force) {
  const double f = force[rule.component];
  return rule.quantity == MpmStopQuantity::force_below ? f - rule.value : rule.value - f;
}

}  // namespace

double mpm_full_body_factor(mpm::Geometry geometry) {
  return geometry == mpm::Geometry::axisymmetric ? 2.0 * kPi : 1.0;
}

MpmPhaseControl::MpmPhaseControl(const MpmCase& c, std::size_t index, mpm::MpmState& state,
                                 bool average_forces)
    : case_(c),
      phase_(c.phases.at(index)),
      state_(state),
      start_time_(state.time()),
      average_forces_(average_forces) {
  for (int b = 0; b < state.rigid_body_count(); ++b) {
    start_velocity_.push_back(state.rigid_body(b).velocity());
    start_displacement_.push_back(state.rigid_body(b).displacement());
  }
  for (const MpmStopRule& rule : phase_.stop_rules) {
    double sense = 0.0;
    if (rule.quantity == MpmStopQuantity::displacement ||
        rule.quantity == MpmStopQuantity::phase_displacement) {
      const double now =
          start_displacement_.at(static_cast<std::size_t>(phase_.stop_body))[rule.component];
      sense = goal(rule) >= now ? 1.0 : -1.0;
    }
    sense_.push_back(sense);
  }
}

double MpmPhaseControl::goal(const MpmStopRule& rule) const {
  if (rule.quantity == MpmStopQuantity::phase_displacement)
    return start_displacement_.at(static_cast<std::size_t>(phase_.stop_body))[rule.component] +
           rule.value;
  return rule.value;
}

void MpmPhaseControl::start(const std::vector<mpm::Vec2>& traction_forces) {
  for (const MpmMaterialChange& change : phase_.material_changes)
    state_.set_material(change.model, change.replacement);
  mpm::Particles& particles = state_.particles();
  if (!traction_forces.empty())
    for (std::size_t p = 0; p < particles.size(); ++p)
      particles.external_force[p] = phase_.traction_multiplier * traction_forces.at(p);
  if (phase_.kind == MpmPhaseKind::geostatic)
    set_geostatic_state(case_, state_, case_.solver.gravity * phase_.gravity_multiplier);
}

mpm::Vec2 MpmPhaseControl::velocity_at(std::size_t body, double time) const {
  const MpmBodyMotion& motion = phase_.body_motion.at(body);
  if (motion.ramp <= 0.0) return motion.velocity;
  const double f = std::clamp((time - start_time_) / motion.ramp, 0.0, 1.0);
  return start_velocity_[body] + f * (motion.velocity - start_velocity_[body]);
}

double MpmPhaseControl::body_speed() const {
  double speed = 0.0;
  for (std::size_t b = 0; b < start_velocity_.size(); ++b) {
    speed = std::max(speed, phase_.body_motion.at(b).velocity.norm());
    if (phase_.body_motion.at(b).ramp > 0.0) speed = std::max(speed, start_velocity_[b].norm());
  }
  return speed;
}

MpmStepPlan MpmPhaseControl::plan_step(double target, double dt) {
  const double now = state_.time();
  MpmStepPlan plan;
  plan.own_step = now + dt < target;
  plan.end = plan.own_step ? now + dt : target;
  auto set_velocities = [&](double length) {
    for (std::size_t b = 0; b < start_velocity_.size(); ++b)
      state_.rigid_body(static_cast<int>(b)).set_velocity(velocity_at(b, now + 0.5 * length));
  };
  set_velocities(plan.end - now);

  // A displacement rule met within this step: shorten it to land on the goal exactly.
  for (std::size_t k = 0; k < phase_.stop_rules.size(); ++k) {
    const MpmStopRule& rule = phase_.stop_rules[k];
    if (sense_[k] == 0.0) continue;
    mpm::RigidBody& body = state_.rigid_body(phase_.stop_body);
    const double remaining = goal(rule) - body.displacement()[rule.component];
    const double speed = body.velocity()[rule.component];
    const double length = plan.end - now;
    if (remaining * sense_[k] <= 0.0 || speed * remaining <= 0.0) continue;
    if (std::abs(speed) * length < std::abs(remaining)) continue;
    const double shortened = remaining / speed;
    plan.own_step = false;
    plan.end = now + shortened;
    plan.landing_rule = static_cast<int>(k);
    set_velocities(shortened);
    mpm::Vec2 v = body.velocity();
    v[rule.component] = remaining / shortened;  // exactly onto the goal
    body.set_velocity(v);
  }
  return plan;
}

void MpmPhaseControl::record_step(double dt) {
  if (phase_.stop_body < 0) return;
  const mpm::Vec2 force =
      state_.rigid_body_force(phase_.stop_body).total * mpm_full_body_factor(case_.geometry);
  // An exponential moving average with time constant τ (the force itself when τ = 0): the
  // exact solution of τ df/dt = F − f over a step with F constant.
  const double tau = average_forces_ ? phase_.stop_force_averaging : 0.0;
  const double weight = has_mean_force_ && tau > 0.0 ? std::exp(-dt / tau) : 0.0;
  mean_force_ = weight * mean_force_ + (1.0 - weight) * force;
  has_mean_force_ = true;
}

PhaseProgress MpmPhaseControl::progress() const {
  PhaseProgress progress{std::clamp((state_.time() - start_time_) / phase_.duration, 0.0, 1.0),
                         "duration_s"};
  for (std::size_t k = 0; k < phase_.stop_rules.size(); ++k) {
    if (sense_[k] == 0.0) continue;
    const MpmStopRule& rule = phase_.stop_rules[k];
    const double from =
        start_displacement_[static_cast<std::size_t>(phase_.stop_body)][rule.component];
    const double to = goal(rule);
    if (to == from) continue;
    const double now = state_.rigid_body(phase_.stop_body).displacement()[rule.component];
    const double fraction = std::clamp((now - from) / (to - from), 0.0, 1.0);
    if (fraction > progress.fraction) progress = {fraction, rule.key};
  }
  return progress;
}

int MpmPhaseControl::met_rule(int landing_rule) const {
  if (phase_.stop_body < 0) return -1;
  const mpm::RigidBody& body = state_.rigid_body(phase_.stop_body);
  for (std::size_t k = 0; k < phase_.stop_rules.size(); ++k) {
    const MpmStopRule& rule = phase_.stop_rules[k];
    const int i = rule.component;
    if (sense_[k] != 0.0) {
      const double d = body.displacement()[i];
      const double g = goal(rule);
      const double tolerance =
          1e-9 * std::abs(g - start_displacement_[static_cast<std::size_t>(phase_.stop_body)][i]);
      if (static_cast<int>(k) == landing_rule || (d - g) * sense_[k] >= -tolerance)
        return static_cast<int>(k);
      continue;
    }
    if (!has_mean_force_) continue;  // no step of this phase yet
    if (rule_margin(rule, mean_force_) < 0.0) return static_cast<int>(k);
  }
  return -1;
}

double MpmPhaseControl::force_margin(int rule) const {
  return rule_margin(
      phase_.stop_rules.at(static_cast<std::size_t>(rule)),
      state_.rigid_body_force(phase_.stop_body).total * mpm_full_body_factor(case_.geometry));
}

std::string MpmPhaseControl::stop_reason(int landing_rule) const {
  const int k = met_rule(landing_rule);
  if (k < 0) return "";
  const MpmStopRule& rule = phase_.stop_rules[static_cast<std::size_t>(k)];
  const MpmBody& b = case_.bodies.at(static_cast<std::size_t>(phase_.stop_body));
  const char* axis[2] = {"x", "y"};
  const int i = rule.component;
  if (sense_[static_cast<std::size_t>(k)] != 0.0)
    return fmt::format("{} = {:.6g}: {} displacement {} = {:.6g} m", rule.key, rule.value, b.name,
                       axis[i], state_.rigid_body(phase_.stop_body).displacement()[i]);
  return fmt::format("{} = {:.6g}: {} force {} = {:.6g} N", rule.key, rule.value, b.name, axis[i],
                     mean_force_[i]);
}

}  // namespace pilempm::simulation
