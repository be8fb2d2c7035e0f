#pragma once
// One centrifuge pile test run (docs/centrifuge.md): the scenario's MPM case is run into
// DIR/mpm/ (particle snapshots, energies, bodies, a checkpoint per phase), and DIR gets what an
// engineer reads: pile.csv (head, tip and shaft force and the tip stress against pile
// displacement and tip depth, with the equilibrium and energy checks), fields_<phase>.csv and
// .vtu at the snapshot depths and phase ends (void ratio, p, q, IGS ρ), summary.json and
// summary.md, and the head-force plots.
#include <filesystem>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "pilempm/scenario/centrifuge_scenario.hpp"
#include "pilempm/study/figures.hpp"

namespace pilempm {

struct CentrifugeRunOptions {
  std::string python;  ///< the interpreter for the plots ("" = the default search)
  bool plots = true;   ///< draw the PNG figures
};

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
  /// At the phase ends: the most particles found deeper than one cell inside the pile (passed
  /// through its surface), the deepest a particle's centre lay inside it [cells of the fine zone]
  /// (the contact holds the grid nodes, so centres may lie a fraction of a cell inside), and the
  /// smallest radius of a particle [mm] (the axis is r = 0).
  std::size_t particles_in_pile = 0;
  double max_penetration_cells = 0.0;
  double min_radius_mm = 0.0;
  std::vector<std::string> field_files;
  std::vector<std::string> figures;
  std::string plot_problem;  ///< "" when the figures were drawn (or not asked for)
};

/// Runs the scenario into `out_dir`; `case_text` (may be empty) is the centrifuge case file's
/// text, kept as DIR/case.toml. Progress lines go to `progress` (nullptr: none).
CentrifugeSummary run_centrifuge(const CentrifugeScenario& scenario, const std::string& case_text,
                                 const std::filesystem::path& out_dir, std::ostream* progress,
                                 const CentrifugeRunOptions& options = {});

/// The built-in quick case (examples/centrifuge/quick.toml), the README's main job.
std::string_view quick_centrifuge_case_text();

/// The figure of the fields (void ratio, p, q, IGS ρ) around the pile after `phase` of a run of
/// `scenario`, from `csv` (a fields_<phase>.csv), drawn into `file`.
FigureSpec centrifuge_field_figure(const CentrifugeScenario& scenario, const std::string& phase,
                                   const std::string& csv, const std::string& file);

/// The column names of pile.csv, in order.
const std::vector<std::string>& centrifuge_pile_columns();

/// summary.json of a run.
std::string centrifuge_summary_json(const CentrifugeSummary& summary);
/// summary.csv of a run: a header and one row of the numbers of summary.json (nan where none).
std::string centrifuge_summary_csv(const CentrifugeSummary& summary);

}  // namespace pilempm
