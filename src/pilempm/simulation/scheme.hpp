#pragma once
// The analysis that advances a case through its phases, as the run loop sees it
// (docs/mpm-case-files.md, "Phases"): a phase is begun with its settings, body motions, material
// changes and tractions; the scheme then advances towards the next point the loop asks for (an
// output or record time, or the phase end), never beyond it, and says whether it got there or
// a stop rule ended the phase. The explicit dynamic analysis (ExplicitScheme) advances in
// time steps; the quasi-static one (QuasiStaticScheme) in load steps of prescribed body
// displacement in pseudo-time, behind the same interface. Both show their state as an
// mpm::MpmState.
#include <cstddef>
#include <string>

#include "pilempm/mpm/mpm_state.hpp"
#include "pilempm/simulation/mpm_case.hpp"

namespace pilempm::simulation {

/// What one Scheme::advance did.
struct Advance {
  double dt = 0.0;          ///< the (pseudo-)time it covered [s]
  bool at_target = false;   ///< it ended exactly at the target it was given
  std::string stop_reason;  ///< the stop rule met at its end ("" when none), e.g.
                            ///< "stop_displacement_y_m = -0.05: pile displacement y = -0.05 m"
};

/// How far a phase is towards its goal.
struct PhaseProgress {
  double fraction = 0.0;  ///< [0, 1]
  std::string goal;       ///< what the fraction measures: "duration_s" or a stop rule's key
};

class Scheme {
 public:
  virtual ~Scheme() = default;

  /// Begins phase `index` of the case at the current time and state: its solver settings, its
  /// material changes, tractions and (geostatic phase) the geostatic state. Returns the stop
  /// rule met already at the start ("" when none).
  virtual std::string begin_phase(std::size_t index) = 0;
  /// Advances the current phase towards `target` (> time(), <= the phase's end time): one step
  /// of the scheme, shortened to end at `target` or exactly on a displacement stop rule.
  virtual Advance advance(double target) = 0;
  /// How far the current phase is: by its stop rule when that is further (a displacement goal),
  /// else by its duration.
  virtual PhaseProgress phase_progress() const = 0;
  /// The latest end of the current phase: its start plus its duration [s].
  virtual double phase_end_time() const = 0;

  /// The (pseudo-)time [s] and the steps taken since t = 0.
  virtual double time() const = 0;
  virtual long steps() const = 0;
  /// The length of the next step [s]: the explicit time step, or the pseudo-time of a load step.
  virtual double step_length() = 0;
  /// Whether the analysis has inertia: its forces of one step carry the noise of the dynamics
  /// and records show their means over time (explicit); without it (quasi-static) every load
  /// step ends in equilibrium and records show the forces at their time.
  virtual bool inertial() const = 0;
  /// A line on the last step for the progress report ("" when there is nothing to say), e.g.
  /// the Newton iterations and cuts of the last load step.
  virtual std::string step_report() const { return ""; }

  /// The state every scheme shares, for output, records and checkpoints: the grid, the
  /// particles and their models, the rigid bodies with their contact forces per surface part,
  /// the boundary reaction, the energies and the run state.
  virtual const mpm::MpmState& state() const = 0;
  /// The same, to be overwritten from a checkpoint on a restart (before the first phase).
  virtual mpm::MpmState& state() = 0;
};

}  // namespace pilempm::simulation
