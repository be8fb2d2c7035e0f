#pragma once
// The typed MPM case (docs/mpm-case-files.md): the geometry, the background grid and its boundary
// conditions (absorbing ones included), the solver settings, the materials, rectangular regions
// filled with particles and their initial state, rigid bodies, surface tractions, and the list of
// phases with their body motions, stop rules and material changes. Everything is SI. The case
// files are read into it by io/mpm_case.hpp; a scenario may build it directly.
#include <array>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pilempm/constitutive/constitutive_model.hpp"
#include "pilempm/constitutive/material_spec.hpp"
#include "pilempm/mpm/grid.hpp"
#include "pilempm/mpm/particles.hpp"
#include "pilempm/mpm/quasi_static/quasi_static_solver.hpp"
#include "pilempm/mpm/rigid_body.hpp"
#include "pilempm/mpm/solver.hpp"

namespace pilempm::simulation {

/// The initial stress of a region.
enum class MpmInitialStress {
  zero,  ///< stress free
  /// σ_v = N g ∫ ρ dz of the regions above, σ_h = K0 σ_v (N of the first phase, and again at
  /// the start of each geostatic phase with its N)
  geostatic,
};

/// One rectangle of particles.
struct MpmRegion {
  std::string name;
  std::string source;       ///< "file:line"
  long line = 0;            ///< the line of its [[region]] header
  std::string key;          ///< "region[i]", for messages
  mpm::RectangleFill fill;  ///< bounds, particles per cell, density; material index set
  MaterialSpec material;
  std::optional<IgsChoice> igs;  ///< hypoplastic only
  bool igs_in_region = false;    ///< igs given in the region (kept when a phase changes sets)
  bool igs_compression = true;   ///< initial IGS fully mobilised by isotropic compression
  MpmInitialStress initial_stress = MpmInitialStress::zero;
  double K0 = 0.0;  ///< σ_h / σ_v of the geostatic stress [-]
  double e0 = 0.0;  ///< initial void ratio as given [-]
  VoidRatioConvention e0_at = VoidRatioConvention::at_initial_stress;
};

/// A rigid body: an axisymmetric pile or a plane-strain convex polygon.
enum class MpmBodyKind { pile, polygon };

struct MpmBody {
  std::string name;
  long line = 0;    ///< the line of its [[body]] header
  std::string key;  ///< "body[i]", for messages
  MpmBodyKind kind = MpmBodyKind::pile;
  double radius = 0.0;              ///< pile [m]
  double tip_y = 0.0;               ///< pile: height of the tip [m]
  double apex_angle = 0.0;          ///< pile: full apex angle of the cone [rad]; π: flat tip
  std::vector<mpm::Vec2> vertices;  ///< polygon [m]
  double friction = 0.0;            ///< μ = tan δ [-]
  double contact_distance = 0.0;    ///< [m]; 0: the solver's default
};

/// The rigid body at its initial position, at rest.
mpm::RigidBody make_rigid_body(const MpmBody& body);

/// A uniform traction on one side of a region, applied as dead-load point forces on the
/// particles of the region's outermost row (column) on that side.
struct MpmTraction {
  long line = 0;
  std::string key;  ///< "traction[i]"
  int region = 0;   ///< index into MpmCase::regions
  mpm::Side side = mpm::Side::top;
  double normal = 0.0;  ///< [Pa], positive pushing into the region
  double shear = 0.0;   ///< [Pa], positive along +x (bottom, top) or +y (left, right)
};

/// How a body moves in a phase: towards `velocity`, reached linearly over `ramp` from its
/// velocity at the phase start, then constant.
struct MpmBodyMotion {
  mpm::Vec2 velocity = mpm::Vec2::Zero();  ///< [m/s]
  double ramp = 0.0;                       ///< [s]
};

/// What a stop rule watches.
enum class MpmStopQuantity {
  displacement,        ///< the body's displacement since t = 0 reaches the value
  phase_displacement,  ///< the body's displacement since the phase start reaches the value
  force_below,         ///< the body's contact force (full body) falls below the value
  force_above,         ///< the body's contact force (full body) rises above the value
};

/// One stop rule of a phase: the phase ends on the step where it is met.
struct MpmStopRule {
  std::string key;  ///< the case-file key, e.g. "stop_displacement_y_m" (named when it ends)
  MpmStopQuantity quantity = MpmStopQuantity::displacement;
  int component = 1;   ///< 0: x, 1: y
  double value = 0.0;  ///< [m] or [N]
};

/// A new parameter set for one material model from a phase start on.
struct MpmMaterialChange {
  int model = 0;         ///< index into MpmCase::models (= the region index)
  std::string material;  ///< the name of the new set
  ModelPtr replacement;
};

enum class MpmPhaseKind {
  standard,   ///< continues from the state the previous phase left
  geostatic,  ///< first (re)sets the K0 stress of the geostatic regions under this phase's N g
};

/// What a phase stands for in a pile test, for what reads its results (a scenario's records,
/// checks and summary); the run does not depend on it. Case files: [[phase]] role.
enum class MpmPhaseRole {
  none,            ///< no role given
  initial_stress,  ///< "initial-stress": the K0 stress settles under N g
  installation,    ///< "installation": the pile is jacked (one or more phases)
  relaxation,      ///< "relaxation": the pile is pulled until its head force is gone
  load_test,       ///< "load-test": the static load test
};

/// "" (none), "initial-stress", "installation", "relaxation", "load-test".
std::string_view to_string(MpmPhaseRole role);

/// The surface parts of a pile (mpm::RigidBody::pile), in the order of its contact forces.
enum class PilePart : std::size_t { tip = 0, shaft = 1, head = 2 };

/// One phase of the run: it ends at its start plus its duration, or earlier on a stop rule.
struct MpmPhase {
  std::string name;
  MpmPhaseKind kind = MpmPhaseKind::standard;
  MpmPhaseRole role = MpmPhaseRole::none;
  double duration = 0.0;                   ///< the longest it runs [s]
  double gravity_multiplier = 1.0;         ///< N [-]
  double local_damping = 0.0;              ///< α [-]
  double output_interval = 0.0;            ///< between VTU snapshots [s]
  double energy_interval = 0.0;            ///< between rows of energies.csv and bodies.csv [s]
  double traction_multiplier = 1.0;        ///< factor on all [[traction]] loads [-]
  bool checkpoint = true;                  ///< write a checkpoint at the phase end
  std::vector<MpmBodyMotion> body_motion;  ///< by body index
  int stop_body = -1;                      ///< the body the stop rules watch (-1: none)
  std::vector<MpmStopRule> stop_rules;
  /// Time constant of the exponential moving average of the force that force stop rules compare
  /// [s]; 0: the force of the last step.
  double stop_force_averaging = 0.0;
  std::vector<MpmMaterialChange> material_changes;
  /// Quasi-static analysis: the largest body travel of one load step [m]; 0: the case's.
  double displacement_step = 0.0;
};

/// One axis of the grid as a case file gives it ([grid.x], [grid.y]): equal cells, or a band of
/// fine cells with cells growing away from it (mpm::GridAxis). Its nodes are MpmCase::x_nodes or
/// y_nodes; a case file is written from it.
struct MpmGridAxis {
  bool graded = false;
  double min = 0.0, max = 1.0;            ///< [m]
  int cells = 1;                          ///< uniform
  double band_min = 0.0, band_max = 0.0;  ///< graded: the fine band [m]
  double fine_spacing = 0.0;              ///< graded: the cell size in the band [m]
  double growth_ratio = 1.0;              ///< graded: of neighbouring cells outside the band
  double max_spacing = std::numeric_limits<double>::infinity();  ///< graded: largest cell [m]

  /// The node coordinates [m] (throws InvalidValue as mpm::GridAxis does).
  std::vector<double> nodes() const {
    return graded ? mpm::GridAxis::graded(min, max, band_min, band_max, fine_spacing, growth_ratio,
                                          max_spacing)
                        .nodes()
                  : mpm::GridAxis::uniform(min, max, cells).nodes();
  }
};

/// Which analysis advances the case (docs/mpm-case-files.md, "Analyses").
enum class MpmAnalysis {
  explicit_dynamic,  ///< "explicit": time steps of the explicit dynamic solver (mpm::Solver)
  quasi_static,      ///< "quasi-static": load steps of static equilibrium (Newton), pseudo-time
};

/// "explicit" or "quasi-static".
std::string_view to_string(MpmAnalysis analysis);

/// The rate integrator's settings where a case's [integrator] does not say: the library's
/// defaults (Heun-Euler) for the explicit analysis, whose time steps are small strain increments
/// that one 2-stage sub-step integrates; Bogacki-Shampine for the quasi-static one, whose load
/// steps are increments of up to several per cent, where the 3rd-order pair needs fewer
/// sub-steps at the same tolerance (docs/quasi-static.md, "The sand model's integration").
IntegratorSettings default_integrator(MpmAnalysis analysis);

struct MpmCase {
  std::string source;  ///< the file name used in messages
  std::string title;
  mpm::Geometry geometry = mpm::Geometry::plane_strain;
  MpmGridAxis x_axis, y_axis;                          ///< the grid as given
  std::vector<double> x_nodes, y_nodes;                ///< their node coordinates [m]
  std::array<mpm::BoundaryCondition, 4> boundaries{};  ///< by mpm::Side
  MpmAnalysis analysis = MpmAnalysis::explicit_dynamic;
  mpm::SolverSettings solver;  ///< the settings of [solver]; phases override some
  /// The quasi-static analysis's own settings; its geometry, shape function, gravity, threads
  /// and volumetric averaging are those of `solver` (simulation::quasi_static_settings).
  mpm::quasi_static::Settings quasi_static;
  /// Quasi-static: the largest body travel of a load step [m]; 0: a tenth of the smallest cell.
  double displacement_step = 0.0;
  IntegratorSettings integrator;  ///< of the models that integrate rates ([integrator])
  /// The case's own [[material]] tables (a region's or a phase's material is one of them or a
  /// built-in set).
  std::vector<MaterialSpec> materials;
  std::vector<std::string> material_names;  ///< index -> name (the regions' materials)
  std::vector<ModelPtr> models;             ///< index -> model
  std::vector<MpmRegion> regions;
  std::vector<MpmBody> bodies;
  std::vector<MpmTraction> tractions;
  std::vector<MpmPhase> phases;
};

}  // namespace pilempm::simulation
