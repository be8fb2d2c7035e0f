#pragma once
// Explicit dynamic material point method in plane strain and axisymmetry.
//
// One step (Sulsky, Chen & Schreyer 1994; MUSL: Sulsky, Zhou & Schreyer 1995):
//   particles to grid: shape functions at x^n, nodal mass, momentum, internal and external forces
//   grid update: local damping, boundary conditions -> nodal velocity and its change over the step
//   contact: rigid bodies correct the nodal velocities (Coulomb friction), force on each body
//   grid to particles: FLIP/PIC velocity and position [MUSL: the new momentum back to the grid]
//   stress update: velocity gradient, Jaumann rotation, constitutive update, deformation
//     gradient, volume, GIMP domain size.
// Three passes over the particles per step: the grid update runs in the node loop of the
// particles-to-grid scatter, the MUSL remap in the grid-to-particle pass. Solver::advance
// (explicit/solver.cpp) names the stages in order; each stage is a function in a file of its own
// under mpm/explicit/ (particles_to_grid, grid_update, contact, xpic, grid_to_particles,
// musl_remap, stress_update, time_step), the lock-free scatter in scatter.hpp and the per-thread
// sums of each stage in thread_tally.hpp.
//
// Mandel components of stress and strain at a particle: 11 = x (r), 22 = y (z), 33 = z (zero
// strain) in plane strain or θθ (hoop) in axisymmetry, 12 = xy (rz); 13 and 23 stay zero.
// Axisymmetry (x = r, y = z) works per radian: V_p = r_p A_p, m_p = ρ V_p; the hoop strain rate
// is Σ S_i v_ri / r_p and the radial internal force gets -V_p σ_θθ S_i / r_p; the radial velocity
// is zero on the axis r = 0.
//
// Threads (OpenMP): particle loops are split statically; the scatter to the grid goes to one
// nodal buffer per thread, summed in thread order, so a run is deterministic for a given thread
// count and differs between thread counts by round-off only.
#include <cstddef>
#include <string>
#include <vector>

#include "pilempm/constitutive/constitutive_model.hpp"
#include "pilempm/mpm/explicit/scatter.hpp"
#include "pilempm/mpm/explicit/thread_tally.hpp"
#include "pilempm/mpm/grid.hpp"
#include "pilempm/mpm/mpm_state.hpp"
#include "pilempm/mpm/particles.hpp"
#include "pilempm/mpm/rigid_body.hpp"
#include "pilempm/mpm/shape_functions.hpp"
#include "pilempm/mpm/surface_contact.hpp"

namespace pilempm::mpm {

/// When the stress is updated. USL takes the velocity gradient from the nodal velocities of the
/// grid update, so a node that a particle barely reaches (small mass, full stress gradient) can
/// be driven unstably, above all with linear shape functions; MUSL maps the new particle
/// velocities back to the grid first, which bounds them (Sulsky, Zhou & Schreyer 1995; Nairn
/// 2003). MUSL is the default.
enum class UpdateScheme {
  usl,   ///< update stress last, from the grid velocities after the grid update
  musl,  ///< modified USL: from the particle velocities mapped back to the grid
};

/// A viscous (absorbing) boundary on one side of the grid (Lysmer & Kuhlemeyer 1969): dashpots
/// at the side's nodes with the traction -ρ c_p v_n normal and -ρ c_s v_t tangential to the
/// side, over each node's share of the side (times r in axisymmetry). A wave arriving normally
/// with these speeds leaves without reflection. The dashpot acts on the free velocity components
/// only; it is integrated implicitly, so it is stable for any coefficient.
struct AbsorbingBoundary {
  Side side = Side::right;
  double density = 0.0;       ///< ρ of the soil behind the side [kg/m^3], > 0
  double p_wave_speed = 0.0;  ///< c_p [m/s], >= 0
  double s_wave_speed = 0.0;  ///< c_s [m/s], >= 0
};

/// How the rigid bodies touch the soil.
enum class ContactScheme {
  /// At the grid nodes within the contact distance of the surface (half a cell by default): the
  /// rigid-body form of the multi-velocity contact on the nodal velocities (contact.cpp).
  nodes,
  /// At the 4 corners of each particle's GIMP domain against the exact surface: the penalty law
  /// with Coulomb friction of the quasi-static solver (mpm/surface_contact.hpp), once per step,
  /// its force spread to the nodes with the hat functions at the corner (surface_contact.cpp).
  surface,
};

struct SolverSettings {
  Geometry geometry = Geometry::plane_strain;
  UpdateScheme scheme = UpdateScheme::musl;
  ShapeFunction shape_function = ShapeFunction::cpgimp;
  /// FLIP/PIC blend of the particle velocity update, in [0, 1]: 1 = FLIP, 0 = PIC. Pure FLIP
  /// keeps particle velocity modes the grid cannot see, which then never decay (the kinetic energy
  /// of a damped quasi-static run stalls); a little PIC removes them.
  double flip_fraction = 0.99;
  /// Order m of the velocity the PIC share of the blend moves toward, XPIC(m) (Hammerquist &
  /// Nairn 2017): 1 = the grid velocity (classic PIC). m > 1 removes the particle velocity modes
  /// the grid cannot see as PIC does, but damps the modes it can see far less: a mode that one
  /// grid round trip keeps by the factor λ keeps 1 - (1 - λ)^m of itself instead of λ. Each order
  /// above 1 costs one more grid round trip per step. In [1, 8].
  int xpic_order = 1;
  double gravity = 9.81;            ///< g [m/s^2], acting along -y
  double gravity_multiplier = 1.0;  ///< N: the body force is N g (centrifuge), >= 0
  double local_damping = 0.0;       ///< α of the local non-viscous damping, in [0, 1)
  double mass_scaling = 1.0;        ///< factor on the inertial mass (not on gravity), >= 1
  double courant_number = 0.5;      ///< in (0, 1]
  double fixed_time_step = 0.0;     ///< > 0: this step [s] instead of the CFL step
  /// Steps between evaluations of the materials' wave speeds for the CFL step (the particle
  /// speeds are taken every step). The stiffness changes little in a few steps and the Courant
  /// number leaves a margin; 1 evaluates every step.
  int wave_speed_interval = 10;
  int threads = 0;  ///< OpenMP threads; 0: default_thread_count (mpm/thread_count.hpp)
  /// Volumetric-locking remedy: the volumetric strain increment of each particle is replaced by
  /// the volume-weighted mean over the particles of its grid cell (the deviatoric part is kept),
  /// in the spirit of B-bar/F-bar (Coombs et al. 2018, "F-bar MPM").
  bool volumetric_smoothing = false;
  ContactScheme contact = ContactScheme::nodes;
  /// The penalty law of contact = surface: penalty_factor β (k_n = β M A / d, as in the
  /// quasi-static solver) and tangential_ratio; its stiffness_margin and vertex_radius are not
  /// used.
  ContactSettings surface_contact;
  /// Dashpots on sides of the grid, at most one per side.
  std::vector<AbsorbingBoundary> absorbing_boundaries;

  /// Throws InvalidValue naming the first setting out of range.
  void validate() const;
};

class Solver final : public MpmState {
 public:
  /// Takes the grid (with its boundary conditions), the particles and the materials the
  /// particles refer to by index. Throws InvalidValue for bad settings, a missing material, a
  /// particle outside the grid or without mass or volume, or r <= 0 in axisymmetry.
  Solver(Grid grid, Particles particles, std::vector<ModelPtr> materials,
         SolverSettings settings = {});

  /// Advances one explicit step and returns its length [s]. Throws pilempm::Error naming the
  /// particle, step and time when a stress update fails or a particle leaves the grid; the
  /// solver's state is then that of a step half done, to be reported, not continued.
  double step();
  /// Steps until the time reaches `end_time` [s] (the last step is shortened to land on it).
  long run_until(double end_time);

  /// The step the next call of step() will take [s]: the fixed step, or the Courant number times
  /// the smallest cell over max_p sqrt(M / (s ρ)) + max_p |v| (an upper bound of
  /// max_p (sqrt(M / (s ρ)) + |v|); M: the model's wave modulus at the particle's state, s: mass
  /// scaling, ρ = m / V current). With contact = surface it is also at most the Courant number
  /// times 2 / ω_c of the penalty springs of the last step, ω_c² = max_i K_i / m_i, K_i = Σ_q
  /// S_i(x_q) k_q over the corners q in contact (a Gershgorin bound of the springs' frequencies on
  /// the lumped nodal masses m_i).
  double next_time_step();

  const char* analysis() const override { return "explicit"; }
  Geometry geometry() const override { return settings_.geometry; }
  double time() const override { return time_; }
  long steps() const override { return steps_; }
  /// N g [m/s^2].
  double gravity() const override { return settings_.gravity * settings_.gravity_multiplier; }
  const Energies& energies() const override { return energies_; }
  const SolverSettings& settings() const { return settings_; }
  /// Changes settings between steps (a new phase), validated.
  void set_settings(const SolverSettings& settings);
  int threads() const override { return threads_; }

  const Grid& grid() const override { return grid_; }
  Grid& grid() { return grid_; }
  const Particles& particles() const override { return particles_; }
  /// For loads and inspection; keep the number of particles unchanged.
  Particles& particles() override { return particles_; }
  const std::vector<ModelPtr>& materials() const override { return materials_; }
  /// Replaces material `index` (a new parameter set for the next phase); states are kept.
  void set_material(int index, ModelPtr model) override;

  /// Adds a rigid body in contact with the soil (Coulomb friction at the grid nodes, see
  /// apply_contact) and returns its index. Throws InvalidValue for a pile in plane strain or a
  /// polygon in axisymmetry.
  int add_rigid_body(RigidBody body);
  int rigid_body_count() const override { return static_cast<int>(rigid_bodies_.size()); }
  /// For changing a body's velocity between steps; the solver moves it by v Δt each step.
  RigidBody& rigid_body(int index) override {
    return rigid_bodies_.at(static_cast<std::size_t>(index));
  }
  const RigidBody& rigid_body(int index) const override {
    return rigid_bodies_.at(static_cast<std::size_t>(index));
  }
  /// The contact force on body `index` in the last step (zero before the first).
  const RigidBodyForce& rigid_body_force(int index) const override {
    return rigid_body_forces_.at(static_cast<std::size_t>(index));
  }

  /// The force the grid's boundary constraints (roller, fixed, the axis) exerted on the soil in
  /// the last step: Σ over constrained node components of m Δv / Δt − f (the force that holds
  /// them), per radian in axisymmetry [N]. Dashpots and contacts are not in it.
  const Vec2& boundary_reaction() const override { return boundary_reaction_; }
  /// The local damping's force on the soil in the last step: Σ over free node components of
  /// −α |f| sign(v), less its share at contact nodes (taken out there), per radian in axisymmetry
  /// [N]. With the boundary reaction, gravity, the contacts and the soil's momentum it closes the
  /// soil's momentum balance; zero without damping.
  Vec2 damping_force() const override { return damping_force_; }
  /// Σ m v_y with the inertial (scaled) mass [kg m/s].
  double vertical_momentum() const override;

  /// The state a checkpoint needs besides particles, bodies and settings.
  SolverRunState run_state() const override;
  /// Restores a checkpoint's run state (after the particles and the bodies; the settings of the
  /// phase are to be set first, since set_settings() forgets the wave speeds). Throws
  /// InvalidValue when the rigid-body forces do not fit the bodies.
  void restore_run_state(const SolverRunState& state) override;

  /// Particle data plus the solver's per-particle scratch [bytes] (with volumetric smoothing
  /// on, its scratch too).
  std::size_t bytes_per_particle() const;

 private:
  // One step of length dt: the stages of the algorithm, in order (solver.cpp).
  void advance(double dt);
  // The stages that are passes of their own, each in its file under mpm/explicit/; the fused
  // per-particle and per-node stages are the classes of particles_to_grid.hpp, grid_update.hpp,
  // grid_to_particles.hpp and musl_remap.hpp.
  // Rigid-body contact on the nodal velocities (contact.cpp): after the grid update also the
  // velocity change for FLIP and the contact forces of the step; after the MUSL remap the
  // velocities only.
  enum class ContactPass { after_grid_update, after_remap };
  void apply_contact(double dt, ContactPass pass);
  // contact = surface (surface_contact.cpp): the penalty forces at the particles' corners at x^n
  // into surface_force_ (per node), the forces on the bodies, the histories and the springs'
  // frequency for the next step.
  void apply_surface_contact(double dt);
  // XPIC(m), m > 1 (xpic.cpp): xpic_shift_ = v* - v^n at the nodes (zero on constrained
  // components).
  void compute_xpic_shift();
  // Whether the PIC share moves toward XPIC(m) with m > 1 (else toward the grid velocity).
  bool xpic_active() const { return settings_.xpic_order > 1 && settings_.flip_fraction < 1.0; }
  // Velocity gradient, Jaumann rotation, constitutive update, F, volume, domain
  // (stress_update.cpp).
  void update_stress(double dt);
  template <class Kinematics>
  void smooth_volumetric_increments(Kinematics&& kinematics);
  void move_rigid_bodies(double dt);
  // The per-thread tallies of a stage into the solver's totals, in thread order.
  void add_grid_update_tallies();
  void add_particle_motion_tallies();

  void check_particles() const;
  // The dashpot coefficients per node from the absorbing boundaries of the settings.
  void update_dashpots();
  [[noreturn]] void fail_at_particle(std::size_t particle, const std::string& reason) const;

  Grid grid_;
  Particles particles_;
  std::vector<ModelPtr> materials_;
  std::vector<const ConstitutiveModel*> models_;  // raw pointers for the particle loops
  SolverSettings settings_;
  int threads_ = 1;

  double time_ = 0.0;
  long steps_ = 0;
  Energies energies_;
  double max_wave_speed_ = 0.0;      // max sqrt(M / (s ρ)) at the last evaluation
  long wave_speed_step_ = -1;        // the step of that evaluation
  double max_particle_speed_ = 0.0;  // max |v_p| after the last step

  // Per-particle scratch: the stencil at x^n and the radius r^n (the stress update needs both
  // after the particles have moved).
  std::vector<Stencil> stencils_;
  std::vector<double> start_radius_;

  // The nodal velocity and its change, side by side for the gathers.
  std::vector<NodeMotion> node_motion_;
  // The per-thread nodal buffers of the scatters to the grid.
  NodeScatter scatter_;

  // XPIC(m) scratch per node: v^n, the current power (S+ S)^k v^n, and the shift v* - v^n that
  // the PIC share adds to the grid velocity (empty while the order is 1).
  std::vector<Vec2> xpic_start_, xpic_power_, xpic_shift_;

  // What each thread adds up in a stage, one tally per thread.
  std::vector<GridUpdateTally> grid_update_tallies_;
  std::vector<ParticleMotionTally> particle_motion_tallies_;
  std::vector<StressUpdateTally> stress_update_tallies_;

  // contact = surface: per particle corner (4 per particle, order of quasi_static) its friction
  // history and its position relative to the body's box_min at the last step (for the slip);
  // per node the contact force of the step and the nodes it touched; the largest Σ k_q / (s m_p).
  struct CornerContact {
    ContactHistory history;
    Vec2 relative_position = Vec2::Zero();
  };
  std::vector<CornerContact> corner_contacts_;
  std::vector<Vec2> surface_force_;
  std::vector<int> surface_nodes_;
  double surface_frequency_squared_ = 0.0;
  // contact = surface: each material's penalty modulus (mpm::penalty_moduli), fixed at the first
  // step as in the quasi-static solver. Empty until fixed.
  std::vector<double> surface_contact_modulus_;

  std::vector<RigidBody> rigid_bodies_;
  std::vector<RigidBodyForce> rigid_body_forces_;
  Vec2 boundary_reaction_ = Vec2::Zero();
  Vec2 damping_force_ = Vec2::Zero();

  // Volumetric smoothing scratch: per particle its increments and cell, per cell the sums.
  struct SmoothedIncrement {
    Mat2 increment;
    double hoop_increment;
    int cell;
  };
  std::vector<SmoothedIncrement> smoothed_;
  std::vector<double> cell_volume_, cell_strain_;

  // Dashpot coefficients per node and direction (empty without absorbing boundaries).
  std::vector<double> dashpot_x_, dashpot_y_;
};

}  // namespace pilempm::mpm
