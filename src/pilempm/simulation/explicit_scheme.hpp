#pragma once
// The explicit dynamic analysis as a Scheme: mpm::Solver's time steps (CFL), each phase run by
// an MpmPhaseControl (body velocities with their ramps, stop rules, the last step shortened to
// land on a displacement goal or on the loop's target time).
#include <optional>
#include <vector>

#include "pilempm/mpm/solver.hpp"
#include "pilempm/simulation/mpm_case.hpp"
#include "pilempm/simulation/phase_control.hpp"
#include "pilempm/simulation/scheme.hpp"

namespace pilempm::simulation {

class ExplicitScheme final : public Scheme {
 public:
  /// The solver of the case at time 0 (make_mpm_solver); `mpm_case` must outlive the scheme.
  explicit ExplicitScheme(const MpmCase& mpm_case);

  std::string begin_phase(std::size_t index) override;
  Advance advance(double target) override;
  PhaseProgress phase_progress() const override;
  double phase_end_time() const override;
  double time() const override { return solver_.time(); }
  long steps() const override { return solver_.steps(); }
  bool inertial() const override { return true; }
  double step_length() override { return solver_.next_time_step(); }
  const mpm::MpmState& state() const override { return solver_; }
  mpm::MpmState& state() override { return solver_; }
  /// The explicit solver itself (its settings, time step, run state).
  const mpm::Solver& solver() const { return solver_; }
  mpm::Solver& solver() { return solver_; }

 private:
  const MpmCase& case_;
  mpm::Solver solver_;
  std::vector<mpm::Vec2> traction_forces_;  // at multiplier 1, by particle (empty: none)
  std::optional<MpmPhaseControl> control_;  // of the current phase
};

}  // namespace pilempm::simulation
