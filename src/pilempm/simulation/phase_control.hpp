#pragma once
// What a phase of an MPM case does besides stepping (docs/mpm-case-files.md, [[phase]]): at its
// start, the new material sets, the traction loads and the geostatic stress; during it, the
// rigid bodies' velocities (with their ramps) and the stop rules, including a last step
// shortened so that a displacement rule is met exactly.
#include <string>
#include <vector>

#include "pilempm/mpm/mpm_state.hpp"
#include "pilempm/simulation/mpm_case.hpp"
#include "pilempm/simulation/scheme.hpp"

namespace pilempm::simulation {

/// Full-body force per solver force: 2π in axisymmetry (the solver's is per radian), 1 in plane
/// strain (per metre).
double mpm_full_body_factor(mpm::Geometry geometry);

/// The next step of a phase as planned by MpmPhaseControl::plan_step.
struct MpmStepPlan {
  bool own_step = true;   ///< a step of the scheme's own length; else shortened to end there
  double end = 0.0;       ///< the time the step ends at [s]
  int landing_rule = -1;  ///< the displacement rule it was shortened to meet exactly (-1: none)
};

class MpmPhaseControl {
 public:
  /// Phase `index` of the case, starting at the state's current time (after a checkpoint has
  /// been read, on a restart), whichever analysis advances it. The analysis's settings are set
  /// by the caller.
  /// `average_forces`: force rules compare the moving average of MpmPhase::stop_force_averaging
  /// (explicit); false: the force at the end of each step (quasi-static, in equilibrium).
  MpmPhaseControl(const MpmCase& mpm_case, std::size_t index, mpm::MpmState& state,
                  bool average_forces = true);

  const MpmPhase& phase() const { return phase_; }
  double start_time() const { return start_time_; }
  /// The latest end: the start plus the duration [s].
  double end_time() const { return start_time_ + phase_.duration; }

  /// The start of the phase: the material changes, the tractions (`traction_forces` at
  /// multiplier 1, one per particle, times the phase's multiplier) and, in a geostatic phase,
  /// the geostatic state.
  void start(const std::vector<mpm::Vec2>& traction_forces);

  /// Plans the next step towards `target` (<= end_time()), `step` [s] long unless shortened to
  /// end at the target or on a displacement goal, and sets the bodies' velocities for it (their
  /// mean over the step, so that velocity times length is the step's displacement).
  MpmStepPlan plan_step(double target, double step);
  /// The largest speed of a body in the phase [m/s] (0: none moves): of its velocity, or of
  /// its velocity at the phase start where a ramp leads from it.
  double body_speed() const;

  /// After a step (or at the start): whether a stop rule is met, and a description of it
  /// ("stop_displacement_y_m = -0.05: pile displacement y = -0.05 m"); "" when none.
  /// `landing_rule`: the plan's, when the step was taken.
  std::string stop_reason(int landing_rule = -1) const;
  /// The stop rule met after a step (-1: none), as stop_reason() finds it.
  int met_rule(int landing_rule = -1) const;
  /// For a force rule: how far the stop body's force is now from meeting it [N], negative
  /// where it is met (force_below: force − value; force_above: value − force). It reads the
  /// body's force of the state as it is, not the moving average.
  double force_margin(int rule) const;

  /// How far the phase is: the largest of the fraction of its duration and, for each
  /// displacement stop rule, the fraction of the way from the phase start to its goal.
  PhaseProgress progress() const;

  /// After each step of length `dt` [s]: updates the averaged force the force rules compare
  /// (MpmPhase::stop_force_averaging).
  void record_step(double dt);

 private:
  mpm::Vec2 velocity_at(std::size_t body, double time) const;
  double goal(const MpmStopRule& rule) const;

  const MpmCase& case_;
  const MpmPhase& phase_;
  mpm::MpmState& state_;
  double start_time_ = 0.0;
  std::vector<mpm::Vec2> start_velocity_;      // by body
  std::vector<mpm::Vec2> start_displacement_;  // by body
  std::vector<double> sense_;                  // by stop rule: +1 / -1 towards a displacement
  mpm::Vec2 mean_force_ = mpm::Vec2::Zero();   // of the stop body, full body [N]
  bool has_mean_force_ = false;
  bool average_forces_ = true;
};

}  // namespace pilempm::simulation
