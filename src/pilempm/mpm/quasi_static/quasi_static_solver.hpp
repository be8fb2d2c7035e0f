#pragma once
// Quasi-static implicit material point method: static equilibrium per load step, solved by
// Newton-Raphson (docs/quasi-static.md).
//
// Updated Lagrangian: the reference of a load step is the last converged configuration (particle
// positions x_n, volumes V_n, GIMP domains). The unknowns are the displacement increments Δu_i of
// the active grid nodes over the step. For an iterate Δu each particle gets
//   G = Σ_i Δu_i ⊗ ∇S_i(x_n)  (the displacement-increment gradient),
//   Δε = sym G (+ the hoop increment Δε_θθ = Σ_i S_i Δu_ri / r_p in axisymmetry),
//   w = ½ (G_yx − G_xy) (the spin), rotated after Hughes & Winget (1980),
// and the stress is integrated by the model from the converged state of the last step, once per
// iteration (never accumulated over iterations). The residual at the free node components is
//   R_i = Σ_p V_p B_i^T σ_p − Σ_p S_i m_p N g (0, −1) − λ Σ_p S_i f_p − f_i^contact,
// B_i the strain-displacement operator (Mandel rows 11, 22, 33, 12; row 33 = S_i / r_p for the
// radial component in axisymmetry, which gives the hoop term V σ_θθ S_i / r_p of the radial
// force). The internal force uses the reference configuration of the step (x_n, V_n): the
// geometric change within one step is neglected in the equilibrium (an error of the order of the
// strain increment, not accumulated over steps).
//
// The Newton matrix is K = Σ_p V_p B^T D_p B + the contact stiffness, D_p the tangent of the
// integrated update: the model's own tangent where it is exact (linear elasticity), else the
// forward-difference perturbation of the integrated update (Fellin & Ostermann 2002), which is
// the consistent tangent to the perturbation's accuracy for any model. K is not symmetric in
// general; it is factorised by a sparse LU (MUMPS, SuiteSparse UMFPACK or Eigen's SparseLU).
//
// Contact with rigid bodies is a penalty law at the corners of the particles' GIMP domains against
// the body's exact surface (RigidBody::query), with Coulomb friction (stick/slip return map on the
// tangential trial force), independent of which grid nodes lie near the surface. See
// surface_contact.hpp.
#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

#include "pilempm/constitutive/constitutive_model.hpp"
#include "pilempm/mpm/grid.hpp"
#include "pilempm/mpm/mpm_state.hpp"
#include "pilempm/mpm/particles.hpp"
#include "pilempm/mpm/quasi_static/linear_solver.hpp"
#include "pilempm/mpm/quasi_static/surface_contact.hpp"
#include "pilempm/mpm/rigid_body.hpp"
#include "pilempm/mpm/shape_functions.hpp"

namespace pilempm::mpm::quasi_static {

/// Which material tangent the Newton matrix uses.
enum class TangentKind {
  automatic,     ///< the model's consistent tangent where it has one in closed form (linear
                 ///< elasticity, Mohr-Coulomb), perturbation for the others
  perturbation,  ///< forward differences of the integrated update, for every model
  elastic,       ///< the model's tangent(state, Δε) (for Mohr-Coulomb the elastic one: modified
                 ///< Newton, linear convergence)
};

/// When the low-stress stabilisation (Settings::low_stress_stiffness) acts.
enum class StabilisationUse {
  /// Only in a load step whose sub-increments failed without it until the cuts ran out: the
  /// failed part is solved again with it (and then without it, Settings::low_stress_resolve),
  /// with the cuts allowed once more. A run that converges without it is not changed by it.
  last_resort,
  /// In every sub-increment: each is solved with it first.
  every_step,
};

/// ContactSettings with vertex_radius = 0.5 (the quasi-static analysis's default).
inline ContactSettings rounded_contact() {
  ContactSettings contact;
  contact.vertex_radius = 0.5;
  return contact;
}

/// The energy tolerance that goes with a force tolerance: 100 f², the ratio of the defaults
/// (1e-6, 1e-10), to 9 significant digits (1e-4 gives 1e-6, not 1.0000000000000002e-06). The
/// energy norm δu·R ≈ Rᵀ K⁻¹ R falls as the square of ||R||, so a force tolerance relaxed
/// without it would leave the energy norm to decide (docs/quasi-static.md, "Convergence").
double energy_tolerance_for(double force_tolerance);

struct Settings {
  Geometry geometry = Geometry::plane_strain;
  ShapeFunction shape_function = ShapeFunction::cpgimp;
  double gravity = 9.81;  ///< g [m/s^2] along −y; the step's multiplier N scales it
  /// Converged when ||R|| <= force_tolerance * F_ref, F_ref the largest of the norms of the
  /// internal, external and contact nodal forces (all active components, so reactions count) ...
  double force_tolerance = 1.0e-6;
  /// ... and |δu_k · R_k| <= energy_tolerance * |δu_1 · R_0| (the energy norm, δu_k the step
  /// taken, R_k the residual after it; it falls
  /// about as the square of ||R||, hence energy_tolerance_for(force_tolerance)).
  double energy_tolerance = 1.0e-10;
  int max_iterations = 25;
  /// A sub-increment still above force_tolerance after max_iterations is accepted, not cut,
  /// when ||R|| <= accept_tolerance * F_ref (the next increment starts from its residual, so the
  /// imbalance is not lost but carried); 0: never (it is cut). Newton's method circles where
  /// the plastic or contact state of a few points changes between iterates; cutting the step
  /// then changes the path by more than this imbalance does (docs/quasi-static.md).
  double accept_tolerance = 1.0e-3;
  /// From this iteration on, a sub-increment below accept_tolerance is accepted at once instead
  /// of iterating on to max_iterations; 0: only after max_iterations. Where Newton circles (a
  /// plastic or contact state changing between iterates) the iterations after it rarely bring
  /// ||R|| much lower: on the pile push, 8 takes 38-46 % fewer iterations than iterating on,
  /// with the head force within 0.4 % (hypoplastic) and 1.5 % (Mohr-Coulomb, whose path moves by
  /// as much with round-off), docs/quasi-static.md, "Convergence".
  int accept_after = 8;
  /// From iteration max(accept_after, stall_iterations + 1) on, a sub-increment whose last
  /// stall_iterations iterations brought no new lowest ||R|| and which is above both
  /// accept_tolerance and force_tolerance is given up at once and cut, instead of iterating on to
  /// max_iterations (Newton's method wandering between 10^-3 and 1 F_ref, as where the plastic and
  /// contact states of a few points keep changing); 0: never. On the centrifuge's parametric base
  /// case 5 would have given up 20 of its 25 failed sub-increments 240 iterations earlier and no
  /// sub-increment that converged (docs/quasi-static.md, "Convergence").
  int stall_iterations = 0;
  /// Backtracking on ||R|| (halving the Newton step up to this many times, 0: none).
  int line_search_steps = 4;
  /// The largest nodal displacement of one Newton step, in cells (of the smallest spacing); a
  /// longer step is scaled down to it. 0: no limit.
  double step_limit = 0.0;
  /// A sub-increment that does not converge is halved, at most this many times per load step.
  int max_cuts = 8;
  /// After a sub-increment that converged in at most `easy_iterations`, the next is doubled (up
  /// to what remains of the step).
  int easy_iterations = 4;
  TangentKind tangent = TangentKind::automatic;
  /// Start the iterations of an increment in which bodies move from the last increment's nodal
  /// displacements scaled to the body motion, where that lowers the residual.
  bool predictor = true;
  /// Relative size of the strain perturbation h = perturbation * max(||Δε||, 1e-6).
  double perturbation = 1.0e-7;
  /// A particle's differentiated tangent (the perturbation's, the costly part of an iteration)
  /// is reused in a later iteration of the same sub-increment while its strain and spin
  /// increments differ from those it was differentiated at by at most this fraction of the
  /// strain increment's norm: Newton's later iterations move most particles by little, and the
  /// tangent's error is then of this order. 0: differentiated in every iteration. The default
  /// took MPM-2's sand model from 170 s to 120 s at about the same iterations (3 160 against
  /// 3 123) and the quick case's from 21 s to 12 s (docs/quasi-static.md, "Reused tangents").
  double tangent_reuse = 0.1;
  /// Whether the Newton matrix holds the derivative of each particle's stress with respect to
  /// its spin increment: the update starts from the converged state turned by the spin
  /// (Hughes-Winget), so the stress depends on the antisymmetric part of the displacement
  /// gradient as well. Off, the matrix misses about σ/E of the stiffness where the stress is
  /// large against the modulus (an elastic pile push then converged linearly, 8 iterations a
  /// step, against 2-3 with it; docs/quasi-static.md, "The spin terms"). On by default.
  bool spin_terms = true;
  /// Whether a load step's strain and spin increments are taken on the increment's midpoint
  /// configuration (Hughes & Winget 1980; midpoint_strain.hpp), a second-order approximation of
  /// the logarithmic strain, or on its start configuration (sym G, first-order: a rotation by θ
  /// gives a spurious normal strain of −θ²/2).
  bool midpoint_strain = true;
  /// A particle whose update ends on the model's mean stress floor (hypoplasticity in tension:
  /// the stress no longer changes with the strain) or whose perturbed update leaves the model's
  /// domain gets, in the Newton matrix only, an isotropic elastic stiffness (ν = 0.3) of this
  /// fraction of the constrained modulus of its converged state. A zero tangent would leave the
  /// nodes such particles alone support without stiffness (the matrix singular); the full
  /// modulus made a push step take 450 iterations instead of 20 (docs/quasi-static.md). The
  /// modulus is the larger of the particle's and its material's reference (the contact's
  /// penalty modulus, fixed at the first load step): a stress-free hypoplastic particle's own
  /// modulus is a thousandth of the sand's at depth, and the nodes it alone reaches had next to
  /// no stiffness (docs/quasi-static.md, "Stress-free sand").
  double floor_stiffness = 1.0e-3;
  /// The same for a particle whose update ended at an apex of its yield surface (Mohr-Coulomb's:
  /// cohesionless sand at the free surface and behind a pile's shoulder), as a fraction of the
  /// same modulus. Such a particle answers a compression with its full elastic stiffness at
  /// once; with no stand-in, the nodes it alone supports have only the ghost springs, and
  /// Newton's steps throw them. Iterations per step of the Mohr-Coulomb pile push from the
  /// surface (bench_quasi_static, 8 steps to 0.4 D, 4 at D/14) at D/4, 6, 8, 10, 14: without the
  /// apex treated so 4.5, 11.2, 12.9, 25.6, 20.0; with this default 4.8, 6.6, 7.4, 14.1, 8.2;
  /// 0.03 and more failed at D/4, the full modulus took 155 at D/10 (docs/quasi-static.md,
  /// "Sand at the Mohr-Coulomb apex").
  double apex_stiffness = 0.01;
  /// A particle whose update ends on the stress floor or at an apex keeps J = V / V_0 at
  /// most this: above it, its deformation gradient and hoop stretch are scaled isotropically
  /// to it (limit_volume_ratio). Sand without stress is loose grains; as a continuum it opened
  /// without bound where Newton iterates pulled its nodes apart (beside the IGS case's pile, a
  /// particle at the heaved surface reached J = 870, its domain 13 x 34 cells, and the nodes it
  /// reached were thrown, docs/quasi-static.md). The default lies above the volume ratio that
  /// hypoplastic sand reaches while it carries stress (its void ratio bounded by e_i).
  /// 0: no limit.
  double floor_volume_ratio = 1.5;
  /// Low-stress stabilisation. Sand that has lost its stress (behind a pile's shoulder, along
  /// its shaft) has almost no stiffness, and where such particles alone support a node, Newton's
  /// method has nothing to hold the node's motion (the full model MPM-2 stalled so at 3 D,
  /// docs/centrifuge.md). A particle whose converged mean stress p is below low_stress_pressure
  /// p_s answers, within each sub-increment, with an added isotropic elastic stress
  ///   σ_s = w η M_c C : (Δε − Δε_ref),   w = 1 − p / p_s,   C of unit constrained modulus
  /// and ν = 0.3, η = low_stress_stiffness, M_c the material's penalty modulus
  /// (ContactSettings), in the residual and the matrix alike (w is fixed by the converged
  /// state, so the residual stays smooth over the iterations). Δε_ref is the particle's strain
  /// increment in the last sub-increment in which a body moved, times the share of that motion
  /// the current one repeats, (d · d_last) / |d_last|² (d: the motion of the body that moves
  /// most; Δε_ref = 0 while no body has moved): the stress resists the change of the particle's
  /// motion from one load step to the next, as inertia does, and vanishes where the sand flows
  /// steadily past a pile. It is not kept past the sub-increment. The stabilisation only finds
  /// the way: each sub-increment solved with it is solved again with less of it, in the stages
  /// of low_stress_continuation, and then without it, each solve starting from the last one's
  /// solution; the solution of the smallest share that converged is kept (a share above 0
  /// counted in LoadStepResult::stabilised, its work booked as damping, Energies::damping).
  /// 0: none. When it acts: low_stress_use.
  double low_stress_stiffness = 0.0;
  StabilisationUse low_stress_use = StabilisationUse::last_resort;
  double low_stress_pressure = 100.0;  ///< p_s [Pa]
  /// Whether a sub-increment solved with the low-stress stabilisation is solved again with less
  /// of it (the default; false keeps every stabilised solution, for tests of the stabilisation).
  bool low_stress_resolve = true;
  /// The shares of η solved in turn between the full stabilisation and none, decreasing, each
  /// in (0, 1). Without stages the solve without the stabilisation, which starts from the
  /// stabilised solution's imbalance (about 10⁻² F_ref in MPM-2), mostly failed there, and the
  /// full stabilisation's solution was kept (docs/centrifuge.md, "The full model").
  std::vector<double> low_stress_continuation = {0.1, 0.01};
  /// Stabilisation of nodes that particles barely reach (cut cells at a free surface or a
  /// body): a node whose support s_i = Σ_p S_ip V_p is below support_threshold times its own
  /// volume v_i (h_x h_y, ∫ r dr dz in axisymmetry) is tied to each of its grid neighbours
  /// with a better support by a ghost spring of stiffness
  ///   k_i = ghost_stiffness · M_i · (1 − s_i / (support_threshold v_i)) (· r_i in axisymmetry),
  /// M_i the largest constrained modulus of the particles it supports. The springs act between
  /// nodes, so they exert no net force (nothing of the load is lost); they only keep the
  /// node's equation away from singular. ghost_stiffness = 0: none.
  double support_threshold = 0.05;
  double ghost_stiffness = 1.0e-3;
  /// A node reached by fewer than this many particles is weak as well, with the weakness
  /// 1 − n / support_particles (the larger of the two counts), and is tied by ghost springs to
  /// its neighbours of lower weakness and, once per pair, of the same: the nodes that one
  /// particle alone reaches have more unknowns than it has strain components (the Newton matrix
  /// singular), and a large particle's volume can pass the support measure above (beside the
  /// IGS case's pile, docs/quasi-static.md). 0: the support measure alone.
  int support_particles = 3;
  /// The weakness w of a node inside a rigid body (its exact surface, at the sub-increment's
  /// start), in [0, 1]: ghost springs of ghost_stiffness · M_i · w tie it to its neighbours
  /// outside. The soil beside the body reaches such a node only with the tails of its shape
  /// functions, yet its domain corners' contact forces act there. 0: none (the default; the
  /// springs stiffen the cut cells beside the pile: docs/quasi-static.md, "Nodes inside a rigid
  /// body").
  double inside_body_weakness = 0.0;
  /// The fastest the build has: MUMPS, else UMFPACK, else Eigen's SparseLU
  /// (docs/quasi-static.md, "The linear solver").
  LinearSolverKind linear_solver = default_linear_solver();
  /// B-bar (Hughes 1980, Int. J. Numer. Meth. Eng. 15): the volumetric strain increment of each
  /// particle is replaced by the volume-weighted mean over the particles of its grid cell, in
  /// the stress update and in the strain-displacement operator (internal force and tangent),
  /// against the volumetric locking of isochoric plastic flow (Tresca, ψ = 0) with 2 x 2
  /// particles per cell (docs/quasi-static.md).
  bool volumetric_averaging = false;
  /// The contact law; the bodies' vertices rounded by half a cell (ContactSettings::vertex_radius:
  /// a penetrated point passing the pile's shoulder then turns its force over an arc instead of
  /// at once; on the hypoplastic pile push this took the push from 0.83 D to 3 D,
  /// docs/quasi-static.md).
  ContactSettings contact = rounded_contact();
  int threads = 0;  ///< OpenMP threads for the particle loops; 0: omp_get_max_threads()
  /// Where to write a line per Newton iteration (a diagnostic: ||R||, the line search, the
  /// contact and the stress floor, the largest residual component and Newton step with their
  /// nodes and forces); nullptr: nowhere. The run loop sets stderr when the environment
  /// variable PILEMPM_NEWTON_TRACE is set (docs/quasi-static.md, "Convergence").
  std::FILE* trace = nullptr;
  /// With `trace`: after each Newton step is solved, the matrix against central differences of
  /// the residual along the step, what the linear model misses over the whole step, by part,
  /// and the particles that miss most (three more evaluations an iteration; a diagnostic).
  /// PILEMPM_NEWTON_TRACE=tangent in a run (docs/quasi-static.md, "Newton trace").
  bool trace_tangent = false;

  /// Throws InvalidValue naming the first setting out of range.
  void validate() const;
};

/// The load of one step: what it reaches at its end.
struct LoadStep {
  /// The pseudo-time the step covers [s] (the parameter of the load path, added to time()).
  double duration = 1.0;
  /// Displacement of each rigid body over the step [m] (empty: none move).
  std::vector<Vec2> body_displacement;
  double gravity_multiplier = 1.0;   ///< N at the end of the step
  double traction_multiplier = 1.0;  ///< λ on the particles' external_force at the end
};

/// One Newton iteration.
struct IterationRecord {
  double residual_norm = 0.0;  ///< ||R|| after the iteration [N]
  double energy_norm = 0.0;    ///< |δu · R_before| [J]
  double line_search = 1.0;    ///< the step length taken
  int contact_points = 0;      ///< contact points in contact after the iteration
  int slipping_points = 0;     ///< of them, slipping
  /// Contact points whose state (out, stick, slip) differs from the iterate before.
  int contact_changes = 0;
  /// Particles whose stress update ended on the model's mean stress floor (tension).
  int floor_particles = 0;
};

/// A converged (or failed) sub-increment of a load step.
struct SubIncrementRecord {
  double fraction = 0.0;          ///< of the load step
  double initial_residual = 0.0;  ///< ||R|| before the first iteration [N]
  double reference_force = 0.0;   ///< F_ref of the force criterion [N]
  bool converged = false;
  /// Accepted after max_iterations at ||R|| / F_ref above force_tolerance (accept_tolerance).
  bool accepted = false;
  /// The share of the low-stress stabilisation's stress kept (Settings::
  /// low_stress_continuation; 1: the full one; 0: none, its solve without it converged).
  double stabilisation_share = 0.0;
  std::vector<IterationRecord> iterations;
};

struct LoadStepResult {
  bool converged = false;
  int iterations = 0;  ///< Newton iterations over all sub-increments, failed ones too
  int cuts = 0;        ///< halvings
  /// Sub-increments accepted after max_iterations (Settings::accept_tolerance) and the largest
  /// ||R|| / F_ref of them.
  int accepted = 0;
  /// Sub-increments that kept the low-stress stabilisation's stress (Settings::
  /// low_stress_stiffness): their solve without it failed.
  int stabilised = 0;
  double largest_stabilisation_share = 0.0;  ///< the largest share of η they kept
  /// Whether the step's cuts without the stabilisation ran out and the rest of the step was
  /// solved with it (StabilisationUse::last_resort).
  bool rescued = false;
  double largest_accepted_residual = 0.0;
  std::vector<SubIncrementRecord> sub_increments;
  std::string message;  ///< why it failed
  /// Time of the parts [s]: model updates and tangents, assembly, factorisation and solve.
  double seconds_material = 0.0, seconds_assembly = 0.0, seconds_factorisation = 0.0;
  /// Particle tangents taken from an earlier iteration instead of differentiated
  /// (Settings::tangent_reuse).
  long reused_tangents = 0;
  int unknowns = 0;  ///< size of the last system
};

/// Contact force on a rigid body [N] (per unit thickness, per radian in axisymmetry), in total
/// and per surface part; a pile pushed into soil gets total.y() > 0.
using BodyForce = RigidBodyForce;

/// The Newton matrix against the residual's derivative (QuasiStaticSolver::check_tangent): along
/// a direction v, K v against the central difference (R(u + h v) − R(u − h v)) / (2 h), in total
/// and by part (the material's internal force; the contact), each as ||difference|| / ||K v||.
struct TangentCheck {
  double total = 0.0, material = 0.0, contact = 0.0;
  double matrix_norm = 0.0;  ///< ||K v|| [N/m]
  /// The unknown with the largest |K v − difference|: its node's position [m] and component.
  Vec2 worst_node = Vec2::Zero();
  int worst_component = 0;
  int unknowns = 0;
};

class QuasiStaticSolver final : public MpmState {
 public:
  /// Throws InvalidValue for bad settings, a missing material, a particle outside the grid or
  /// without volume, or r <= 0 in axisymmetry. The gravity and traction multipliers start at 0.
  QuasiStaticSolver(Grid grid, Particles particles, std::vector<ModelPtr> materials,
                    Settings settings = {});

  /// Solves one load step (cut and retried where needed). Converged: the state has advanced to
  /// the end of the step. Not converged: the state is that at the start of the step.
  LoadStepResult solve_step(const LoadStep& load);

  /// Adds a rigid body; returns its index. Throws InvalidValue for a pile in plane strain or a
  /// polygon in axisymmetry.
  int add_rigid_body(RigidBody body);
  int rigid_body_count() const override { return static_cast<int>(bodies_.size()); }
  const RigidBody& rigid_body(int index) const override { return bodies_.at(std::size_t(index)); }
  RigidBody& rigid_body(int index) override { return bodies_.at(std::size_t(index)); }
  /// The contact force on body `index` at the end of the last step.
  const BodyForce& body_force(int index) const { return body_forces_.at(std::size_t(index)); }
  const RigidBodyForce& rigid_body_force(int index) const override { return body_force(index); }
  /// The force the grid's constraints exert on the soil at the end of the last step [N].
  const Vec2& boundary_reaction() const override { return boundary_reaction_; }
  /// The largest penetration into a body of a contact point that carries force (those on the
  /// axis of an axisymmetric model have no area) at the end of the last step [m].
  double max_penetration() const { return max_penetration_; }

  double gravity_multiplier() const { return gravity_multiplier_; }
  double traction_multiplier() const { return traction_multiplier_; }
  /// The sum of the accepted steps' durations: the load path's parameter [s].
  double pseudo_time() const { return time_; }

  const char* analysis() const override { return "quasi-static"; }
  Geometry geometry() const override { return settings_.geometry; }
  double time() const override { return time_; }
  /// Load steps accepted since t = 0.
  long steps() const override { return steps_; }
  /// N g at the end of the last step [m/s^2].
  double gravity() const override { return settings_.gravity * gravity_multiplier_; }
  int threads() const override { return threads_; }
  /// The work account [J], accumulated over the accepted steps (trapezoidal rule): internal
  /// (Σ V σ:Δε), external (gravity and tractions) and contact_work (of the bodies on the soil,
  /// Σ F_body · Δd_body); no kinetic energy, no damping.
  const Energies& energies() const override { return energies_; }
  const Grid& grid() const override { return grid_; }
  const Particles& particles() const override { return particles_; }
  Particles& particles() override { return particles_; }
  const std::vector<ModelPtr>& materials() const override { return materials_; }
  const Settings& settings() const { return settings_; }
  /// Replaces material `index`; states are kept.
  void set_material(int index, ModelPtr model) override;

  /// The time, steps, energies, body forces and, as scheme arrays, the contact points with
  /// their friction history, the last nodal displacements and the load multipliers.
  SolverRunState run_state() const override;
  /// Restores a checkpoint's run state (after the particles and the bodies). Throws InvalidValue
  /// when the arrays do not fit the particles, the grid or the bodies.
  void restore_run_state(const SolverRunState& state) override;
  /// Checks the Newton matrix (for tests and diagnostics; the state does not change): at the
  /// iterate a sub-increment of `load` of the given fraction starts from (the predictor where it
  /// is taken, else zero), along a fixed pseudo-random direction whose largest nodal component
  /// is `relative_step` cells.
  TangentCheck check_tangent(const LoadStep& load, double fraction = 1.0,
                             double relative_step = 1.0e-6) const;
  /// Nodal displacement of the last accepted step (x, y per node; zero where inactive) [m].
  const std::vector<Vec2>& last_node_displacement() const { return node_displacement_; }
  /// The Newton matrix of the last iteration (free components of the active nodes), for
  /// inspection of its conditioning.
  const SparseMatrix& last_matrix() const { return last_matrix_; }
  /// The linear solver's work so far (factorisations, solves, mixed precision's refinements and
  /// fallbacks to double precision).
  const LinearSolverCounts& linear_counts() const { return linear_solver_.counts(); }
  LinearSolverKind linear_solver_kind() const { return linear_solver_.kind(); }

 private:
  struct Trial;         // the per-particle results of one evaluation of an iterate
  struct TangentCache;  // the tangents differentiated in a sub-increment (Settings::tangent_reuse)
  struct StepSetup;
  struct Committed;

  bool solve_sub_increment(double fraction, const LoadStep& load, SubIncrementRecord& record,
                           LoadStepResult& result);
  // A sub-increment's targets, linear in its fraction of the step from the current state.
  struct Targets {
    double gravity = 0.0, traction = 0.0;
    std::vector<Vec2> body_step;  // per body
  };
  Targets targets(double fraction, const LoadStep& load) const;
  void build_setup(StepSetup& setup) const;
  // " (particle i at x, y: the model's reason)" for the trial's failed stress update, or "".
  std::string failed_update(const Trial& trial) const;
  // The Newton matrix's fixed pattern and the scatter maps of a set-up (StepSetup::pattern).
  void build_pattern(StepSetup& setup) const;
  // The predictor of a sub-increment: the last increment's nodal displacements scaled to this
  // one's body motion (empty where there is none).
  std::vector<double> prediction(const StepSetup& setup, const std::vector<Vec2>& body_step) const;
  // Evaluates the iterate: stresses, internal/external/contact forces, residual; with
  // `tangent`, the Newton matrix too. Returns false when a model update fails.
  bool evaluate(const StepSetup& setup, const std::vector<double>& du, double gravity,
                double traction, const std::vector<Vec2>& body_step, bool tangent, Trial& trial,
                LoadStepResult& result, TangentCache* cache = nullptr) const;
  // Diagnostic (Settings::trace_tangent): the Newton matrix against central differences of the
  // residual along the Newton step at the iterate du, by part and by particle.
  void trace_tangent_along(const StepSetup& setup, const std::vector<double>& du,
                           const Eigen::VectorXd& step, double gravity, double traction,
                           const std::vector<Vec2>& body_step, const Trial& at,
                           const SparseMatrix& matrix) const;
  // Keeps the contact points within |l| of their particle along x and y (corner_position_),
  // each drawn back along the segment to its particle, and never deeper into a body than it was.
  void bound_corners();
  void commit(const StepSetup& setup, const std::vector<double>& du, const Trial& trial,
              double gravity, double traction, const std::vector<Vec2>& body_step);

  Grid grid_;
  Particles particles_;
  std::vector<ModelPtr> materials_;
  Settings settings_;
  int threads_ = 1;
  std::vector<RigidBody> bodies_;
  std::vector<BodyForce> body_forces_;
  /// Tangential contact force per particle corner at the last converged state (4 per particle).
  std::vector<ContactHistory> contact_history_;
  /// The contact points: the corners of the particles' domains at creation, moved since with
  /// the particles' affine motion (4 per particle) [m], and at the end of each sub-increment
  /// (and the start of each load step) drawn back along the segment to the particle until within
  /// |l| of it along x and y (l its domain's half-lengths, |l| at most one cell of the grid at
  /// the particle), never deeper into a body (bound_corners): sand sheared along a pile's shaft
  /// carried its corners 20 cells away, where ∇S_k · (x_q − x_p) multiplied their forces and
  /// motions by 20 (MPM-2, docs/quasi-static.md).
  std::vector<Vec2> corner_position_;
  /// The modulus of the contact penalty per material [Pa]: the largest constrained modulus of
  /// the material's particles at the first load step, then fixed (a penalty that followed the
  /// particles' stiffness would change the force of an unchanged penetration between steps;
  /// all 0: not fixed yet).
  std::vector<double> contact_modulus_;
  double last_body_step_ = 0.0;  // largest body displacement of the last increment [m]
  /// The low-stress stabilisation's reference (Settings::low_stress_stiffness): each particle's
  /// strain increment in the last sub-increment in which a body moved, and that motion [m]
  /// (empty and zero without the stabilisation or before any body moved).
  std::vector<Vec6> reference_strain_;
  Vec2 reference_motion_ = Vec2::Zero();
  /// The share of the low-stress stabilisation in force (1; lowered while a sub-increment is
  /// solved again with less of it, 0 without it).
  double stabilisation_scale_ = 1.0;
  /// Whether the rest of a load step is being solved with the stabilisation after its cuts ran
  /// out without it (StabilisationUse::last_resort).
  bool rescuing_ = false;
  /// Whether the stabilisation acts in the sub-increment being solved.
  bool stabilisation_on() const {
    return settings_.low_stress_stiffness > 0.0 &&
           (settings_.low_stress_use == StabilisationUse::every_step || rescuing_);
  }
  Vec2 boundary_reaction_ = Vec2::Zero();
  double max_penetration_ = 0.0;
  double gravity_multiplier_ = 0.0, traction_multiplier_ = 0.0, time_ = 0.0;
  long steps_ = 0;
  Energies energies_;
  std::vector<Vec2> node_displacement_;
  LinearSolver linear_solver_;
  SparseMatrix last_matrix_;
};

}  // namespace pilempm::mpm::quasi_static
