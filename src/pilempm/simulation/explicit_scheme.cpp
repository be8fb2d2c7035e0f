// The explicit dynamic analysis as a Scheme: see explicit_scheme.hpp.
#include "pilempm/simulation/explicit_scheme.hpp"

#include "pilempm/core/error.hpp"
#include "pilempm/simulation/case_assembly.hpp"
#include "pilempm/simulation/tractions.hpp"

namespace pilempm::simulation {

ExplicitScheme::ExplicitScheme(const MpmCase& mpm_case)
    : case_(mpm_case), solver_(make_mpm_solver(mpm_case)) {
  if (!mpm_case.tractions.empty())
    traction_forces_ = mpm_traction_forces(mpm_case, solver_.particles());
}

std::string ExplicitScheme::begin_phase(std::size_t index) {
  solver_.set_settings(phase_settings(case_, case_.phases.at(index)));
  control_.reset();
  control_.emplace(case_, index, solver_);
  control_->start(traction_forces_);
  return control_->stop_reason();
}

Advance ExplicitScheme::advance(double target) {
  if (!control_) throw Error("ExplicitScheme::advance: no phase begun");
  const MpmStepPlan plan = control_->plan_step(target, solver_.next_time_step());
  const double step_start = solver_.time();
  if (plan.own_step)
    solver_.step();
  else
    solver_.run_until(plan.end);
  Advance advance;
  advance.dt = solver_.time() - step_start;
  control_->record_step(advance.dt);
  advance.stop_reason = control_->stop_reason(plan.landing_rule);
  advance.at_target = !plan.own_step && plan.landing_rule < 0;
  return advance;
}

PhaseProgress ExplicitScheme::phase_progress() const {
  return control_ ? control_->progress() : PhaseProgress{};
}

double ExplicitScheme::phase_end_time() const {
  return control_ ? control_->end_time() : solver_.time();
}

}  // namespace pilempm::simulation
