#pragma once
// What every MPM analysis (explicit dynamic, quasi-static) holds and shows, whatever advances it:
// the grid, the particles and their models, the rigid bodies with the contact forces on them, the
// reaction of the grid's constraints, the energy (work) account, the (pseudo-)time and the step
// count. Output, records, phase control and checkpoints read and set the state through this
// interface (docs/mpm-case-files.md, "Analyses").
#include <string>
#include <utility>
#include <vector>

#include "pilempm/constitutive/constitutive_model.hpp"
#include "pilempm/mpm/grid.hpp"
#include "pilempm/mpm/particles.hpp"
#include "pilempm/mpm/rigid_body.hpp"
#include "pilempm/mpm/shape_functions.hpp"

namespace pilempm::mpm {

/// Energy account of the run [J] (per unit thickness in plane strain, per radian in
/// axisymmetry). kinetic + internal + damping + absorbed - external_work - contact_work is
/// conserved (up to the time discretisation and the frictional slip at contacts).
struct Energies {
  /// ½ Σ m v² (inertial mass) at the end of the last step (at construction: initial velocities).
  /// The velocities belong to mid-step (x_n+1 = x_n + Δt v_n+1), so kinetic + internal at one
  /// step oscillates by about ωΔt/2 around the conserved total in a vibration.
  double kinetic = 0.0;
  double internal = 0.0;       ///< strain work Σ V σ:Δε, accumulated
  double external_work = 0.0;  ///< work of gravity and particle loads, accumulated
  double damping = 0.0;        ///< dissipated by local damping, accumulated
  /// Work of the rigid bodies on the soil, -Σ F_body . v_body Δt, accumulated. The kinetic energy
  /// lost when soil nodes are brought to the body's velocity (impacts) and by frictional slip is
  /// not in the account, so the balance closes up to these losses.
  double contact_work = 0.0;
  double absorbed = 0.0;  ///< dissipated by absorbing boundaries, accumulated
};

/// Contact force on a rigid body over the last step [N] (per unit thickness in plane strain, per
/// radian in axisymmetry): minus the soil's nodal momentum corrections over Δt, in total and per
/// surface part (indexed as the body's part_names()). A pile pushed into soil gets total.y() > 0.
struct RigidBodyForce {
  Vec2 total = Vec2::Zero();
  std::vector<Vec2> parts;
};

/// What a step carries to the next besides particles, rigid bodies and settings: a checkpoint
/// stores it, and a restart restores it, so that the run continues bitwise.
struct SolverRunState {
  double time = 0.0;
  long steps = 0;
  Energies energies;
  double max_wave_speed = 0.0;      ///< at the last evaluation of the wave speeds
  long wave_speed_step = -1;        ///< the step of that evaluation (-1: none yet)
  double max_particle_speed = 0.0;  ///< max |v_p| after the last step
  std::vector<RigidBodyForce> rigid_body_forces;
  /// What only one analysis carries (the quasi-static contact points and their friction
  /// history, the load multipliers reached), as named flat arrays: a checkpoint stores them as
  /// they are, so that it need not know the analysis.
  std::vector<std::pair<std::string, std::vector<double>>> scheme_arrays;
};

class MpmState {
 public:
  virtual ~MpmState() = default;

  /// The analysis that advances the state: "explicit" or "quasi-static".
  virtual const char* analysis() const = 0;
  virtual Geometry geometry() const = 0;
  /// The (pseudo-)time [s]: in the quasi-static analysis the parameter of the load path.
  virtual double time() const = 0;
  /// Time steps (explicit) or load steps (quasi-static) taken since t = 0.
  virtual long steps() const = 0;
  /// The body force acting now, N g [m/s^2] along −y.
  virtual double gravity() const = 0;
  /// OpenMP threads of the particle loops.
  virtual int threads() const = 0;

  virtual const Grid& grid() const = 0;
  virtual const Particles& particles() const = 0;
  virtual Particles& particles() = 0;
  virtual const std::vector<ModelPtr>& materials() const = 0;
  /// Replaces material `index` (a phase's new parameter set); the particles' states are kept.
  virtual void set_material(int index, ModelPtr model) = 0;

  virtual int rigid_body_count() const = 0;
  virtual const RigidBody& rigid_body(int index) const = 0;
  virtual RigidBody& rigid_body(int index) = 0;
  /// The contact force on body `index` over the last step.
  virtual const RigidBodyForce& rigid_body_force(int index) const = 0;
  /// The force the grid's constraints exert on the soil over the last step [N].
  virtual const Vec2& boundary_reaction() const = 0;
  /// The force of the local damping on the soil over the last step [N] (zero without inertia).
  virtual Vec2 damping_force() const { return Vec2::Zero(); }
  /// Σ m v_y with the inertial mass [kg m/s] (zero without inertia).
  virtual double vertical_momentum() const { return 0.0; }
  virtual const Energies& energies() const = 0;

  /// What a checkpoint stores besides particles, bodies and settings, and a restart restores.
  virtual SolverRunState run_state() const = 0;
  virtual void restore_run_state(const SolverRunState& state) = 0;
};

}  // namespace pilempm::mpm
