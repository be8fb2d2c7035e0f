#pragma once
// The centrifuge pile test (docs/study.md §4) described by its physics: the pile, the g-level, the
// container, the sand and its parameter sets, the installation, relaxation and load-test rules,
// and a mesh fineness. From it the scenario builds a complete MPM case (docs/mpm-case-files.md):
// the graded axisymmetric grid, the sand region with its K0 stress, the pile wished in place and
// the phases. The defaults are those of docs/study.md §4; docs/centrifuge.md marks the assumed
// ones.
#include <optional>
#include <string>
#include <vector>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/constitutive/material_spec.hpp"
#include "pilempm/simulation/mpm_case.hpp"

namespace pilempm::scenario {

/// How the pile moves in one phase of the scenario.
struct PileMotion {
  double velocity = 0.0;  ///< speed of the pile [m/s], > 0 (the direction is the phase's)
  double ramp = 0.0;      ///< time to reach it from the previous phase's velocity [s]
};

struct CentrifugeScenario {
  std::string title = "centrifuge pile test";

  // The test (model scale).
  double pile_diameter = 0.0113;  ///< D [m]
  double g_level = 40.0;          ///< N: body force N g [-]
  double gravity = 9.81;          ///< g [m/s^2]
  double container_radius_D = 26.0;
  double sand_height_D = 35.0;

  // The sand. A material is a built-in set name or the name of one of `materials` (the
  // scenario's [[material]] tables, which become the case's), of any registered model: the
  // hypoplastic sets, Mohr-Coulomb or linear elasticity. igs, e0_at = "zero-pressure" and a
  // load-test set apply to hypoplastic sand only; every model carries the void ratio e0.
  double e0 = 0.68;
  std::string e0_at = "initial-stress";  ///< "initial-stress" or "zero-pressure" (hypoplastic)
  std::optional<double> density;         ///< [kg/m^3]; default ρ_d = G_s ρ_w / (1 + e0)
  double grain_density = 2650.0;         ///< G_s ρ_w [kg/m^3] (G_s = 2.65 assumed)
  std::optional<double> K0;              ///< default: the installation material's (scenario_K0)
  std::string igs = "IGS3";  ///< of hypoplastic sand; other models have no intergranular strain
  std::string installation_material = "original";  ///< the set of the K0 and installation phases
  std::string load_test_material;                  ///< "" = the installation set
  std::vector<MaterialSpec> materials;  ///< the [[material]] tables as read (the typed case's)
  IntegratorSettings integrator{};      ///< the [integrator] table as read
  /// The friction angle of the installation material when it is a [[material]] table [deg]: φ_c
  /// of a hypoplastic set, φ of a Mohr-Coulomb one, 0 for a model without one (linear
  /// elasticity); the reader sets it (material_friction_angle_deg), built-in sets are looked up.
  double material_phi_c_deg = 0.0;

  // The pile.
  std::string tip = "conical";  ///< "conical" or "flat"
  double apex_angle_deg = 60.0;
  std::optional<double> interface_friction_angle_deg;  ///< default 2/3 φ_c

  // The analysis: explicit dynamics (the default) or quasi-static load steps of at most
  // displacement_step_D of pile travel (docs/mpm-case-files.md, "Analyses"). The settings from
  // mass_scaling to xpic_order, the local damping of the phases and the relaxation's force
  // averaging belong to the explicit analysis and are not used by the quasi-static one.
  simulation::MpmAnalysis analysis = simulation::MpmAnalysis::explicit_dynamic;
  double displacement_step_D = 0.025;
  /// The contact's normal force smoothed over this fraction of the particle size
  /// (mpm::ContactSettings::smoothing; quasi-static analysis only, docs/centrifuge.md).
  double contact_smoothing = 0.05;
  /// Newton's force tolerance (mpm::quasi_static::Settings::force_tolerance; quasi-static
  /// analysis only): 1e-4 of the reference force, not the library's 1e-6: 21 % fewer Newton
  /// iterations on the quick case, its head force within 0.3 % and its capacity within 2 %
  /// (docs/centrifuge.md, "Newton's tolerance").
  double force_tolerance = 1.0e-4;
  /// Newton's energy tolerance (mpm::quasi_static::Settings::energy_tolerance: |δu_k · R_k| at
  /// most this fraction of the first iteration's; quasi-static analysis only); unset:
  /// energy_tolerance_for(force_tolerance), 100 f². The force tolerance 1e-4 as energy tolerance
  /// took 28 % fewer iterations on MPM-2's first 2 D but 6 % more on the whole of MPM-2, with
  /// more cut load steps (docs/centrifuge.md, "Newton's tolerance").
  std::optional<double> energy_tolerance;
  /// A load step still above force_tolerance is accepted from its 8th Newton iteration on once
  /// ||R|| is below this fraction of F_ref, and after max_iterations if below it (cut otherwise)
  /// (mpm::quasi_static::Settings::accept_tolerance; quasi-static analysis only); 0: never
  /// accepted above force_tolerance. The strict pair (force_tolerance 1e-5, this 1e-4) took
  /// MPM-2 1.65 times as long and left the spread of its paths as it was (docs/centrifuge.md,
  /// "Newton's tolerance").
  double accept_tolerance = mpm::quasi_static::Settings{}.accept_tolerance;
  /// Newton's stall rule (mpm::quasi_static::Settings::stall_iterations; quasi-static analysis
  /// only): a load step without a new lowest residual in 5 iterations is cut at once; 0: never.
  int stall_iterations = 5;
  /// Reuse of the particles' differentiated tangents within a load step
  /// (mpm::quasi_static::Settings::tangent_reuse; quasi-static analysis only): while a particle's
  /// strain increment has changed by at most this fraction; 0: none.
  double tangent_reuse = mpm::quasi_static::Settings{}.tangent_reuse;
  /// Newton's step limit in cells (mpm::quasi_static::Settings::step_limit; quasi-static
  /// analysis only): a Newton step that moves a grid node by more than this many cells is
  /// scaled down to it; 0: none. One cell by default: where the pile reverses (the
  /// relaxation's first load step, the load test's reloading), a first Newton step of up to 14
  /// cells at grid nodes inside the pile had made MPM-2 at D/8 spend 601 iterations and 15 cuts
  /// in two such load steps; with the limit 21 and none (docs/centrifuge.md, "Newton's step
  /// limit").
  double newton_step_limit_cells = 1.0;
  /// The low-stress stabilisation (mpm::quasi_static::Settings::low_stress_stiffness and
  /// low_stress_pressure; quasi-static analysis only, docs/centrifuge.md): 0, none; by default
  /// η = 3 only in a load step that fails without it (low_stress_use): MPM-3 stopped at 7.0 D
  /// without it and ran every phase so, 2 of its 425 load steps finished with it.
  double low_stress_stiffness = 3.0;
  double low_stress_pressure_Pa = 100.0;
  mpm::quasi_static::StabilisationUse low_stress_use =
      mpm::quasi_static::StabilisationUse::last_resort;
  /// Ghost springs for the grid nodes inside the pile (mpm::quasi_static::Settings::
  /// inside_body_weakness; quasi-static analysis only): 0, none (the default; measured in
  /// docs/quasi-static.md, "Nodes inside a rigid body").
  double inside_body_weakness = 0.0;

  // The phases.
  double wished_in_place_D = 10.0;  ///< tip depth below the surface when the pile is put in
  double installation_D = 10.0;     ///< jacked further; 0: no installation (MPM-1)
  // 0.025 m/s with Courant 0.9: at D/6 the speed check passes from 0.05 to 0.025 m/s (−1.6 %)
  // and from 0.025 to 0.0125 m/s (−1.3 %), so 0.025 m/s is one halving on the safe side; the
  // study's former 0.1 m/s gives a force about 12 % too high (docs/verification.md §8).
  PileMotion jacking{0.025, 0.002};
  bool relaxation = true;
  PileMotion relaxation_motion{0.01, 0.002};
  double relaxation_max_D = 0.05;  ///< pulling stops at the latest after this much travel
  /// Pulling stops when the head force's moving average with this time constant falls below
  /// zero [s] (the force of one step is noisy).
  double relaxation_force_averaging = 0.002;
  double load_test_D = 0.1;  ///< 0: no load test
  PileMotion load_test_motion{0.02, 0.002};
  double initial_stress_time = 0.05;    ///< length of the K0 phase [s]
  double initial_stress_damping = 0.7;  ///< local damping while the K0 stress settles [-]
  double damping = 0.0;                 ///< local damping of the other phases [-]
  /// Penetrations (tip depth below the surface, in D) at which the fields are written; the
  /// ends of installation and load test are always written.
  std::vector<double> snapshot_depths_D;
  double record_interval_D = 0.05;  ///< pile travel between rows of the force records

  // The mesh and solver.
  double cells_per_D = 4.0;             ///< cell size D / cells_per_D in the fine zone
  double fine_radius_D = 3.0;           ///< the fine zone reaches this far from the axis
  double fine_depth_below_tip_D = 4.0;  ///< and this far below the deepest tip
  double headroom_D = 3.0;              ///< grid above the sand surface (room for heave)
  double growth_ratio = 1.15;           ///< of the cells outside the fine zone
  int particles_per_cell = 2;           ///< per direction, in the fine zone
  /// Per direction outside the fine zone. The sand there deforms little: one particle a cell
  /// moved the head force by less than 1 % against two and took a third less time on the small
  /// model, half the particles on the full one (docs/verification.md §8).
  int particles_per_cell_outside = 1;
  double mass_scaling = 100.0;
  // 0.9 rather than 0.5: the PIC share's viscosity grows with the steps per unit of time, so the
  // larger step is both cheaper (1.8 times fewer steps) and closer to the slow limit (§8).
  double courant_number = 0.9;
  int threads = 0;
  bool volumetric_smoothing = true;
  // A PIC share blended in at every step acts as an artificial viscosity at the tip that grows
  // with the number of steps per unit of time; pure FLIP removes that but lets the noise that
  // makes the force fall with the jacking speed grow (docs/verification.md §8). 0.99 is the
  // setting with the smallest speed dependence measured so far.
  double flip_fraction = 0.99;
  int xpic_order = 1;  ///< XPIC(m) order of the PIC share's target (1: classic PIC)

  // Derived quantities.
  double container_radius() const { return container_radius_D * pile_diameter; }
  double sand_height() const { return sand_height_D * pile_diameter; }
  double pile_radius() const { return 0.5 * pile_diameter; }
  /// The tip's height when the pile is wished in place [m].
  double initial_tip_y() const { return sand_height() - wished_in_place_D * pile_diameter; }
  /// ρ of the sand [kg/m^3].
  double sand_density() const { return density ? *density : grain_density / (1.0 + e0); }
};

/// The friction angle of a material [deg]: φ_c of a hypoplastic set, φ of a Mohr-Coulomb
/// material, 0 for a model without one (linear elasticity).
double material_friction_angle_deg(const MaterialSpec& material);
/// The scenario's material by name: one of its [[material]] tables, else a built-in set (throws
/// InvalidValue when neither).
MaterialSpec scenario_material(const CentrifugeScenario& scenario, const std::string& name);
/// Whether the installation material is a hypoplastic set (built-in or a [[material]] table).
bool scenario_sand_is_hypoplastic(const CentrifugeScenario& scenario);
/// The friction angle of the installation material [deg]: that of its [[material]] table, else
/// the built-in set's φ_c, else material_phi_c_deg. Used for the defaults of K0 and δ.
double scenario_friction_angle_deg(const CentrifugeScenario& scenario);
/// K0 used: the given one, else the model's at-rest value of the installation material (1 − sin
/// φ_c hypoplastic, 1 − sin φ Mohr-Coulomb, ν / (1 − ν) linear elastic).
double scenario_K0(const CentrifugeScenario& scenario);
/// δ used [deg]: the given one or 2/3 of the installation material's friction angle (a model
/// without one needs it given: validate() says so).
double scenario_interface_friction_deg(const CentrifugeScenario& scenario);

/// Checks that the pieces fit together (the pile inside the sand, the fine zone inside the
/// container, ...). Throws InvalidValue naming the key of the scenario file.
void validate(const CentrifugeScenario& scenario);

/// A phase of the case: its name and its role.
struct ScenarioPhase {
  std::string name;
  simulation::MpmPhaseRole role = simulation::MpmPhaseRole::none;
};

/// The phases the case will have, in order: "initial-stress", "installation" (split at the
/// snapshot depths as "installation-to-4.7D", ..., each with the installation role),
/// "relaxation", "load-test".
std::vector<ScenarioPhase> scenario_phases(const CentrifugeScenario& scenario);
/// Their names.
std::vector<std::string> scenario_phase_names(const CentrifugeScenario& scenario);

/// The typed MPM case of the scenario, built directly: the graded axisymmetric grid, the sand
/// regions with their K0 stress, the pile wished in place and the phases with their roles. Its
/// numbers have 9 significant digits, as a person would write them; io/mpm_case_writer.hpp
/// writes it for the record as mpm_case.toml, which runs the same. `source_name` names the case
/// in messages. Throws InvalidValue as validate() does.
simulation::MpmCase centrifuge_case(const CentrifugeScenario& scenario,
                                    const std::string& source_name);

}  // namespace pilempm::scenario
