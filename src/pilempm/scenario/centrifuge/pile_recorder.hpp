#pragma once
// The pile of a centrifuge run as it is recorded (docs/centrifuge.md, pile.csv): an observer of
// the run loop that takes a row per record interval of pile travel and at every phase end, each
// with the forces averaged over the time since the previous row.
#include <optional>
#include <string>
#include <vector>

#include "pilempm/mpm/mpm_state.hpp"
#include "pilempm/scenario/centrifuge/centrifuge_scenario.hpp"
#include "pilempm/simulation/body_force_means.hpp"
#include "pilempm/simulation/run_loop.hpp"

namespace pilempm::scenario {

/// One row of pile.csv, as numbers.
struct PileRow {
  double time = 0.0;
  std::string phase;
  simulation::MpmPhaseRole role = simulation::MpmPhaseRole::none;
  double displacement = 0.0;                      ///< pile, down positive [m]
  double phase_displacement = 0.0;                ///< since the phase start, down positive [m]
  double tip_depth = 0.0;                         ///< below the sand surface [m]
  double head = 0.0, tip = 0.0, shaft = 0.0;      ///< [N]
  double base_reaction = 0.0, soil_weight = 0.0;  ///< [N]
  double kinetic = 0.0, pile_work = 0.0;          ///< [J]
  double momentum_rate = 0.0;  ///< the sand's vertical momentum (scaled mass): mean dP/dt [N]
  double damping = 0.0;        ///< the local damping's vertical force on the sand, mean [N]

  /// F_head − (R_base − W): zero in static equilibrium, D − dP/dt of the sand in general.
  double equilibrium_residual() const { return head - (base_reaction - soil_weight); }
  /// The sand's momentum balance dP/dt = R_base + D − W − F_head, as residual + dP/dt − D: zero
  /// when every force on the sand is booked.
  double force_book_closure() const { return equilibrium_residual() + momentum_rate - damping; }
};

/// Records the pile (body 0) during the run: one row per record interval of pile travel in
/// installation phases, ten per interval in the others (none during the initial stress), and
/// one at every phase end.
class PileRecorder final : public simulation::RunObserver {
 public:
  /// `factor`: full pile per solver force (simulation::mpm_full_body_factor).
  PileRecorder(const CentrifugeScenario& scenario, double factor);

  /// On a restart (first_phase > 0) the recorder goes on from the pile's place in the
  /// restored state, after the rows given back by restore().
  void run_start(const simulation::Scheme& scheme, std::size_t first_phase) override;
  void after_step(const simulation::Scheme& scheme, const simulation::MpmPhase& phase,
                  double dt) override;
  void phase_end(const simulation::Scheme& scheme, const simulation::MpmPhase& phase) override;

  const std::vector<PileRow>& rows() const { return rows_; }

  /// The rows so far as text (to 17 digits, a run's checkpoint keeps them) and back; taken at
  /// a phase end, where no means are pending. restore() throws Error on text it did not write.
  std::string saved() const;
  void restore(const std::string& saved);

 private:
  void add_row(const mpm::MpmState& solver, const simulation::MpmPhase& phase);

  const CentrifugeScenario& s_;
  double factor_;
  double interval_;
  simulation::MpmBodyForceMeans means_;
  mpm::Vec2 reaction_impulse_ = mpm::Vec2::Zero();
  mpm::Vec2 damping_impulse_ = mpm::Vec2::Zero();
  double elapsed_ = 0.0;
  bool stepped_ = false;                         // a step since the last row
  mpm::Vec2 last_reaction_ = mpm::Vec2::Zero();  // of the last step [N]
  double last_row_y_ = 0.0;
  double phase_start_y_ = 0.0;
  double momentum_ = 0.0;              // [N s], at the last row
  std::optional<double> soil_weight_;  // [N], summed at the first row
  std::vector<PileRow> rows_;
};

}  // namespace pilempm::scenario
