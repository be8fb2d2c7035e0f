#pragma once
// Output of MPM runs (docs/mpm-case-files.md, "Output"): a VTU snapshot of the particles (and
// one of the rigid bodies' polygons) per output time with a ParaView series (particles.pvd), the
// energy account as CSV (energies.csv), the rigid bodies' motion and forces as CSV (bodies.csv),
// the quasi-static analysis's Newton work per load step (load_steps.csv) and checkpoints, as an
// observer of the run loop (simulation/run_loop.hpp, which decides when). Files are written
// atomically.
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "pilempm/io/vtu_writer.hpp"
#include "pilempm/mpm/mpm_state.hpp"
#include "pilempm/mpm/quasi_static/linear_solver.hpp"
#include "pilempm/simulation/mpm_case.hpp"
#include "pilempm/simulation/run_loop.hpp"

namespace pilempm {

namespace simulation {
struct LoadStepRecord;  // simulation/quasi_static_scheme.hpp
}  // namespace simulation

/// The size R of the intergranular strain of each of the solver's models (0: none), by which
/// ρ = ||δ|| / R.
std::vector<double> mpm_igs_sizes(const mpm::MpmState& solver);

/// The particles as a point cloud, with the fields listed in docs/mpm-case-files.md.
/// `initial_position` gives the displacement; `material_index` maps a model index to the index
/// of its material name (what the "material" field holds).
PointCloud mpm_particle_cloud(const mpm::MpmState& solver,
                              const std::vector<mpm::Vec2>& initial_position,
                              const std::vector<int>& material_index);

/// The outline of a rigid body as drawn, counter-clockwise: its polygon (for a pile the section
/// mirrored about the axis) cut off above the height `top` [m] (a pile's head lies far above the
/// grid); with `half_section` also cut at x = 0, keeping x >= 0 (a pile's half-section, for
/// figures in r and depth). Empty when nothing of it is left.
std::vector<mpm::Vec2> mpm_body_outline(const mpm::RigidBody& body, double top,
                                        bool half_section = false);

/// The solver's rigid bodies for ParaView (bodies_NNNNN.vtu): one polygon per body at its
/// current position (mpm_body_outline cut at the grid's top), z = 0, with the cell field "body"
/// (the body's index).
PolygonMesh mpm_body_mesh(const mpm::MpmState& solver);

/// The header of energies.csv (a comment line with the units, then the column names).
std::string mpm_energies_header(mpm::Geometry geometry);
/// One row of energies.csv; `time_step` is the step the analysis takes from there (the CFL
/// step, or a load step's pseudo-time) [s].
std::string mpm_energies_row(const mpm::MpmState& solver, double time_step);

/// The header of load_steps.csv (quasi-static analysis: a comment line with the units, then the
/// column names) and one row of it: the Newton work of the load step that ended at the solver's
/// time, in `phase`.
std::string mpm_load_steps_header();
std::string mpm_load_steps_row(const mpm::MpmState& solver, const std::string& phase,
                               const simulation::LoadStepRecord& record, double penetration);

/// The header of bodies.csv (a comment line with the units, then the column names): one
/// force_y_<part>_N column per surface part name of the solver's bodies.
std::string mpm_bodies_header(const mpm::MpmState& solver);
/// One row per body of bodies.csv at the solver's time; `body_names` by body index, `phase` the
/// name of the phase. Forces are those of the full body in axisymmetry (2π times the solver's
/// per-radian force; the radial force_x is 0: it cancels around the axis), per metre in plane
/// strain: `forces` by body index when given (the means since the previous row), else those of
/// the solver's last step.
std::string mpm_bodies_rows(const mpm::MpmState& solver, const std::vector<std::string>& body_names,
                            const std::string& phase,
                            const std::vector<mpm::RigidBodyForce>* forces = nullptr);

/// What a run did.
struct MpmRunSummary {
  long steps = 0;
  double time = 0.0;
  double wall_seconds = 0.0;
  std::vector<std::filesystem::path> vtu_files;                ///< written by this run
  std::filesystem::path pvd_file, energies_file, bodies_file;  ///< bodies_file: empty if none
  std::filesystem::path load_steps_file;            ///< quasi-static analysis only, else empty
  std::vector<simulation::MpmPhaseEnd> phase_ends;  ///< the phases this run ran, in order
  std::vector<std::filesystem::path> checkpoints;   ///< written by this run
  std::size_t first_phase = 0;                      ///< > 0 when restarted
  simulation::MpmAnalysis analysis = simulation::MpmAnalysis::explicit_dynamic;
  /// Quasi-static: Newton iterations and cuts over the run, the most iterations of one load
  /// step, and the largest penetration of a contact point into a body [m].
  long newton_iterations = 0, newton_cuts = 0;
  int most_newton_iterations = 0;
  /// Load steps (or parts) accepted after max_iterations (accept_tolerance), and the largest
  /// ||R|| / F_ref of them.
  long newton_accepted = 0;
  double largest_accepted_residual = 0.0;
  /// Sub-increments that kept the low-stress stabilisation's stress.
  long newton_stabilised = 0;
  long newton_rescued = 0;  ///< load steps finished with the stabilisation after their cuts
  double max_penetration = 0.0;
  /// The linear solver ("mumps-mixed", ...) and its work over the run.
  std::string linear_solver;
  mpm::quasi_static::LinearSolverCounts linear_counts;
};

/// State of a caller's own (a scenario's observers': the pile recorded so far, its checks) that
/// goes into every checkpoint of the run as a named record and comes back on a restart from it.
class CheckpointedState {
 public:
  virtual ~CheckpointedState() = default;
  /// The record's name in the checkpoint: unique, not one of the run's own (energies.csv,
  /// bodies.csv, load_steps.csv, particles.pvd).
  virtual std::string record_name() const = 0;
  /// The state at a checkpoint after `phases_done` phases: at the end of the last of them, or,
  /// where `at_phase_end` is false, in the middle of the next one (the last converged state of
  /// a quasi-static phase that failed, last_converged_checkpoint_*.h5).
  virtual std::string save(std::size_t phases_done, bool at_phase_end) const = 0;
  /// The state of the checkpoint `file` (written after `phases_done` phases), before the first
  /// phase of the restarted run; `saved` is empty when the checkpoint has no such record.
  /// Throws InputError naming the file when the checkpoint cannot continue this run.
  virtual void restore(const std::string& saved, std::size_t phases_done,
                       const std::filesystem::path& file) = 0;
};

/// What a caller may do during a run, besides the files: observers of the run loop
/// (simulation/run_loop.hpp), told after the files' own writer and the progress line, and
/// state kept in the checkpoints.
struct MpmRunHooks {
  std::vector<simulation::RunObserver*> observers;
  std::vector<CheckpointedState*> checkpointed;
  /// The progress stream is a terminal: one line updated in place (else a line every 10 s).
  bool progress_on_terminal = false;
};

/// Runs the phases of a case with the case's analysis (explicit or quasi-static,
/// simulation::run_phases), writing into
/// `out_dir` (created if needed): particles_NNNNN.vtu,
/// particles.pvd, energies.csv, with rigid bodies bodies.csv and bodies_NNNNN.vtu (listed in
/// particles.pvd as part 1 at the particles' times), and at the end of each phase that
/// asks for it checkpoint_NN_<phase>.h5 (NN: the number of phases done). Progress lines and the
/// end of each phase go to `progress` (nullptr: none). With `restart` (a checkpoint file), the
/// run continues from it with the case's phases from the checkpoint's next phase on and the
/// case's materials (with the material changes of the phases before), and its output files
/// start with the records the checkpoint holds. Throws Error naming the phase when the solver
/// fails; what was written up to then stays valid.
MpmRunSummary run_mpm_case(const simulation::MpmCase& mpm_case,
                           const std::filesystem::path& out_dir, std::ostream* progress,
                           const std::filesystem::path& restart = {},
                           const MpmRunHooks& hooks = {});

/// The file name of the checkpoint after `phases_done` phases, the last one named `phase`:
/// checkpoint_NN_<phase>.h5 with characters other than letters, digits, '-', '_' and '.'
/// replaced by '_'.
std::string mpm_checkpoint_name(std::size_t phases_done, const std::string& phase);

}  // namespace pilempm
