#pragma once
// The quasi-static analysis as a Scheme (docs/quasi-static.md, docs/mpm-case-files.md,
// "Analyses"): each advance is one load step of mpm::quasi_static::QuasiStaticSolver, static
// equilibrium at its end found by Newton's method. Time is pseudo-time: a phase's body
// velocities times pseudo-time give the body displacements, so the same case file describes the
// same load path in both analyses. A load step moves the bodies by at most the displacement step
// (the phase's displacement_step_m, else the case's), is shortened to land on an output time or
// a displacement stop rule, and a phase in which no body moves goes from one output time to the
// next in one step each (its gravity, traction and material changes applied in its first step).
// Force stop rules compare the force at the end of each load step (no averaging: every step ends
// in equilibrium); the load step in which one is first met is bisected, so that the phase ends
// where the force crosses the rule's value, to 2.4e-4 of the step.
#include <optional>
#include <vector>

#include "pilempm/mpm/quasi_static/quasi_static_solver.hpp"
#include "pilempm/simulation/mpm_case.hpp"
#include "pilempm/simulation/phase_control.hpp"
#include "pilempm/simulation/scheme.hpp"

namespace pilempm::simulation {

/// The Newton work of load-step solves, summed: of one advance (one load step, or the solves of
/// a load step in which a force stop rule is bisected; a row of the run's load_steps.csv), or of
/// the whole run.
struct LoadStepRecord {
  long solves = 0;  ///< load-step solves: 1 per advance, or 2 + the bisections of a force rule
  long iterations = 0, cuts = 0;
  long accepted = 0;                       ///< sub-increments accepted above the tolerance
  double largest_accepted_residual = 0.0;  ///< the largest ||R|| / F_ref of them
  long stabilised = 0;  ///< sub-increments that kept the low-stress stabilisation's stress
  double largest_stabilisation_share = 0.0;  ///< the largest share of it they kept
  /// Solves whose cuts without the stabilisation ran out and that were finished with it
  /// (mpm::quasi_static::StabilisationUse::last_resort).
  long rescued = 0;
  int most_iterations = 0;  ///< of one solve
  int unknowns = 0;         ///< of the last system
  double material_seconds = 0.0, assembly_seconds = 0.0, factorisation_seconds = 0.0;
  double wall_seconds = 0.0;

  /// Adds one solve that took `seconds` of wall time.
  void add(const mpm::quasi_static::LoadStepResult& step, double seconds);
};

class QuasiStaticScheme final : public Scheme {
 public:
  /// The solver of the case at time 0 (make_quasi_static_solver); `mpm_case` must outlive the
  /// scheme. Throws InputError naming the case file when the case needs inertia (initial
  /// velocities, absorbing boundaries).
  explicit QuasiStaticScheme(const MpmCase& mpm_case);

  std::string begin_phase(std::size_t index) override;
  /// One load step; throws Error naming the load step, the pseudo-time and why when it does not
  /// converge after the allowed cuts (the state is then that of the last converged step).
  Advance advance(double target) override;
  PhaseProgress phase_progress() const override;
  double phase_end_time() const override;
  double time() const override { return solver_.time(); }
  long steps() const override { return solver_.steps(); }
  bool inertial() const override { return false; }
  double step_length() override;
  std::string step_report() const override;
  const mpm::MpmState& state() const override { return solver_; }
  mpm::MpmState& state() override { return solver_; }

  const mpm::quasi_static::QuasiStaticSolver& solver() const { return solver_; }
  /// The last load step's Newton record.
  const mpm::quasi_static::LoadStepResult& last_step() const { return last_step_; }
  /// The last advance's Newton work (over its bisections too).
  const LoadStepRecord& last_advance() const { return last_advance_; }
  /// Over the run: Newton iterations, cuts, the largest iterations of one step and the largest
  /// penetration of a contact point [m].
  long total_iterations() const { return total_.iterations; }
  long total_cuts() const { return total_.cuts; }
  /// Load steps (or parts) accepted above the force tolerance (Settings::accept_tolerance) and
  /// the largest ||R|| / F_ref of them.
  long total_accepted() const { return total_.accepted; }
  double largest_accepted_residual() const { return total_.largest_accepted_residual; }
  /// Sub-increments that kept the low-stress stabilisation's stress (Settings::
  /// low_stress_stiffness).
  long total_stabilised() const { return total_.stabilised; }
  /// Load steps finished with the low-stress stabilisation after their cuts ran out.
  long total_rescued() const { return total_.rescued; }
  int most_iterations() const { return total_.most_iterations; }
  double max_penetration() const { return max_penetration_; }

 private:
  double displacement_step() const;
  // One load step of `duration` [s] of pseudo-time with the bodies' current velocities; throws
  // Error when it does not converge.
  void solve_load_step(double duration);

  const MpmCase& case_;
  mpm::quasi_static::QuasiStaticSolver solver_;
  std::vector<mpm::Vec2> traction_forces_;  // at multiplier 1, by particle (empty: none)
  std::optional<MpmPhaseControl> control_;  // of the current phase
  std::size_t phase_ = 0;
  mpm::quasi_static::LoadStepResult last_step_;
  LoadStepRecord last_advance_, total_;  // of the last advance; of the run
  double max_penetration_ = 0.0;
};

}  // namespace pilempm::simulation
