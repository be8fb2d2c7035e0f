#pragma once
// What a centrifuge run measured and whether it holds together (docs/centrifuge.md, summary):
// the checks at each phase end (no particle through the pile or across the axis; after the
// initial stress, σ_v against ρ N g z), and the summary of the recorded pile: the head force at
// the end of installation, the peak tip stress, relaxation, capacity, and the equilibrium and
// energy windows.
#include <cstddef>
#include <string>
#include <vector>

#include "pilempm/scenario/centrifuge/centrifuge_scenario.hpp"
#include "pilempm/scenario/centrifuge/pile_recorder.hpp"
#include "pilempm/simulation/run_loop.hpp"

namespace pilempm::scenario {

/// What a run measured (NaN where the run has no such phase). Forces of the full pile [N].
struct CentrifugeSummary {
  std::string title;
  std::size_t particles = 0;
  long steps = 0;
  double wall_seconds = 0.0;
  /// After the K0 phase: max |σ_v − ρ N g z| / (ρ N g H) over the particles beyond 2 D from the
  /// pile, and the mean of σ_v / (ρ N g z) over those deeper than 1 D.
  double initial_stress_error = 0.0;
  double initial_stress_ratio = 0.0;
  double installation_head_force = 0.0;  ///< mean over the last cell of travel of installation
  double installation_tip_depth_D = 0.0;
  double peak_tip_stress_MPa = 0.0;  ///< max of the recorded tip stress during installation
  double peak_tip_stress_depth_D = 0.0;
  double relaxation_travel_mm = 0.0;  ///< how far relaxation pulled the pile up
  double capacity = 0.0;              ///< head force at the end of the load test (0.1 D)
  double load_test_displacement_mm = 0.0;
  /// Equilibrium during installation: max |F_head − (R_base − W)| / F_head over windows of one
  /// cell of travel with F_head above half its final value.
  double equilibrium_error = 0.0;
  /// The same over windows of 1 D of travel (many periods of the sand column's ringing).
  double equilibrium_error_1D = 0.0;
  /// The same as equilibrium_error with the rate of the sand's vertical momentum (scaled mass)
  /// added and the local damping's force taken off: F_head − (R_base − W) + dP/dt − D is zero up
  /// to round-off when the forces are booked right, so equilibrium_error is the sand's inertia
  /// (and, in a run with damping, the damping's force).
  double equilibrium_closure = 0.0;
  /// max kinetic energy (with the scaled mass) / pile work during installation after the first
  /// D of travel.
  double max_kinetic_to_work = 0.0;
  /// The smoothness of the head force during installation (head_force_scatter): over the last
  /// D of travel, and the largest over the whole D of travel from the start of installation and
  /// the last D, with where that D starts [D of travel] (NaN with less than 1 D of travel; a D
  /// with fewer than 5 rows is left out).
  double scatter_last_D = 0.0;
  double largest_scatter = 0.0;
  double largest_scatter_from_D = 0.0;
  /// At the phase ends: the most particles found deeper than one cell inside the pile (passed
  /// through its surface), the deepest a particle's centre lay inside it [cells of the fine zone]
  /// (the contact holds the grid nodes, so centres may lie a fraction of a cell inside), and the
  /// smallest radius of a particle [mm] (the axis is r = 0).
  std::size_t particles_in_pile = 0;
  double max_penetration_cells = 0.0;
  double min_radius_mm = 0.0;
  std::vector<std::string> field_files;
  std::string restarted_from;  ///< the checkpoint the run continued from ("" from the start)
  std::vector<std::string> figures;
  std::string plot_problem;  ///< "" when the figures were drawn (or not asked for)
};

/// The checks at each phase end, into a summary: the particles inside the pile, the smallest
/// radius, and after the initial stress phase the K0 check (and `particles`).
class CentrifugeChecks final : public simulation::RunObserver {
 public:
  CentrifugeChecks(const CentrifugeScenario& scenario, CentrifugeSummary& summary);
  void phase_end(const simulation::Scheme& scheme, const simulation::MpmPhase& phase) override;

 private:
  const CentrifugeScenario& s_;
  CentrifugeSummary& summary_;
};

/// The K0 check into `summary`: σ_v against ρ N g z beyond 2 D from the pile.
void initial_stress_check(const CentrifugeScenario& scenario, const mpm::Solver& solver,
                          CentrifugeSummary& summary);

/// The head force's scatter over a stretch of travel: the root-mean-square deviation of the
/// recorded head forces about their least-squares quadratic in the travel, over their mean
/// (docs/verification.md §8, the smoothness check); NaN for fewer than 5 rows, sizes
/// that differ or a mean that is not positive.
double head_force_scatter(const std::vector<double>& travel, const std::vector<double>& head);

/// The figures of the summary from the recorded pile: installation head force and tip depth,
/// peak tip stress, relaxation travel, capacity, equilibrium windows, kinetic energy share,
/// head-force scatter.
void summarise_pile(const CentrifugeScenario& scenario, const std::vector<PileRow>& rows,
                    CentrifugeSummary& summary);

}  // namespace pilempm::scenario
