#include "pilempm/scenario/centrifuge/centrifuge_scenario.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>

#include "pilempm/constitutive/hypoplastic/hypoplastic_parameters.hpp"
#include "pilempm/constitutive/model_registry.hpp"
#include "pilempm/constitutive/mohr_coulomb/mohr_coulomb.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/core/number_text.hpp"
#include "pilempm/core/tensor.hpp"
#include "pilempm/mpm/grid.hpp"

namespace pilempm::scenario {

namespace {

bool is_builtin_set(const std::string& name) {
  const std::vector<std::string> names = hypoplastic_set_names();
  return std::find(names.begin(), names.end(), name) != names.end();
}

void require(bool ok, const std::string& key, double value, const std::string& allowed) {
  if (!ok) throw InvalidValue(key, format_value(value), allowed);
}

// The tip depths (below the surface) [D] where the installation is split, in order, the end of
// the installation last.
std::vector<double> installation_stops_D(const CentrifugeScenario& s) {
  std::vector<double> stops;
  const double end = s.wished_in_place_D + s.installation_D;
  std::vector<double> snapshots = s.snapshot_depths_D;
  std::sort(snapshots.begin(), snapshots.end());
  for (double depth : snapshots)
    if (depth > s.wished_in_place_D + 1e-9 && depth < end - 1e-9) stops.push_back(depth);
  stops.push_back(end);
  return stops;
}

std::string depth_label(double depth_D) {
  return fmt::format("{:g}D", depth_D);
}

// The travel time of a phase with a generous margin, as its duration (its stop rule ends it).
double phase_duration(double travel, const PileMotion& motion) {
  return 2.0 * travel / motion.velocity + 2.0 * motion.ramp + 1e-3;
}

}  // namespace

double material_friction_angle_deg(const MaterialSpec& material) {
  if (material.is_hypoplastic()) return material.hypoplastic().phi_c_deg;
  if (const auto* mc = material.parameters_as<MohrCoulombParameters>())
    return mc->friction_angle_deg;
  return 0.0;
}

MaterialSpec scenario_material(const CentrifugeScenario& s, const std::string& name) {
  for (const MaterialSpec& m : s.materials)
    if (m.name == name) return m;
  return builtin_material(name);
}

bool scenario_sand_is_hypoplastic(const CentrifugeScenario& s) {
  return std::none_of(s.materials.begin(), s.materials.end(), [&](const MaterialSpec& m) {
    return m.name == s.installation_material && !m.is_hypoplastic();
  });
}

double scenario_friction_angle_deg(const CentrifugeScenario& s) {
  for (const MaterialSpec& m : s.materials)
    if (m.name == s.installation_material) return material_friction_angle_deg(m);
  if (is_builtin_set(s.installation_material))
    return hypoplastic_set(s.installation_material).phi_c_deg;
  return s.material_phi_c_deg;
}

double scenario_K0(const CentrifugeScenario& s) {
  if (s.K0) return *s.K0;
  // A [[material]] of another model: its own at-rest value (ν / (1 − ν) for linear elasticity).
  for (const MaterialSpec& m : s.materials)
    if (m.name == s.installation_material && !m.is_hypoplastic())
      return model_registry().at(m.model).at_rest_K0(*m.parameters);
  return 1.0 - std::sin(scenario_friction_angle_deg(s) * std::numbers::pi / 180.0);
}

double scenario_interface_friction_deg(const CentrifugeScenario& s) {
  if (s.interface_friction_angle_deg) return *s.interface_friction_angle_deg;
  return 2.0 / 3.0 * scenario_friction_angle_deg(s);
}

void validate(const CentrifugeScenario& s) {
  require(s.pile_diameter > 0.0, "test.pile_diameter_mm", s.pile_diameter * 1e3, "> 0");
  require(s.g_level > 0.0, "test.g_level", s.g_level, "> 0");
  require(s.sand_height_D > 0.0, "test.sand_height_D", s.sand_height_D, "> 0");
  require(s.container_radius_D >= s.fine_radius_D + 1.0, "test.container_radius_D",
          s.container_radius_D,
          fmt::format(">= mesh.fine_radius_D + 1 = {:g}", s.fine_radius_D + 1.0));
  require(s.fine_radius_D >= 1.0, "mesh.fine_radius_D", s.fine_radius_D,
          ">= 1 (the pile and a ring around it)");
  require(s.e0 > 0.0, "sand.e0", s.e0, "> 0");
  require(s.wished_in_place_D >= 0.0, "installation.wished_in_place_D", s.wished_in_place_D,
          ">= 0");
  require(s.installation_D >= 0.0, "installation.depth_D", s.installation_D, ">= 0");
  const double deepest = s.wished_in_place_D + s.installation_D;
  const double room_below = s.fine_depth_below_tip_D + 1.0;
  require(deepest + room_below <= s.sand_height_D, "installation.depth_D", s.installation_D,
          fmt::format("<= test.sand_height_D - installation.wished_in_place_D - "
                      "mesh.fine_depth_below_tip_D - 1 = {:g} (the tip must stay in the fine "
                      "zone, above the container bottom)",
                      s.sand_height_D - s.wished_in_place_D - room_below));
  require(s.installation_D > 0.0 || s.load_test_D > 0.0, "load_test.displacement_D", s.load_test_D,
          "> 0 when there is no installation (the run must move the pile)");
  for (double depth : s.snapshot_depths_D)
    require(depth > s.wished_in_place_D && depth <= deepest, "installation.snapshot_depths_D",
            depth,
            fmt::format("in ({:g}, {:g}] (tip depths below the surface [D] the pile passes "
                        "during installation)",
                        s.wished_in_place_D, deepest));
  require(s.cells_per_D >= 1.0, "mesh.cells_per_D", s.cells_per_D, ">= 1");
  require(s.jacking.velocity > 0.0, "installation.velocity_m_per_s", s.jacking.velocity, "> 0");
  require(s.relaxation_motion.velocity > 0.0, "relaxation.velocity_m_per_s",
          s.relaxation_motion.velocity, "> 0");
  require(s.load_test_motion.velocity > 0.0, "load_test.velocity_m_per_s",
          s.load_test_motion.velocity, "> 0");
  require(s.record_interval_D > 0.0, "output.record_interval_D", s.record_interval_D, "> 0");
  const bool own_table =
      std::any_of(s.materials.begin(), s.materials.end(),
                  [&](const MaterialSpec& m) { return m.name == s.installation_material; });
  if (!is_builtin_set(s.installation_material) && !own_table)
    require(s.material_phi_c_deg > 0.0, "sand.material", s.material_phi_c_deg,
            "a built-in set or a [[material]] table of the file");
  if (!s.interface_friction_angle_deg && !(scenario_friction_angle_deg(s) > 0.0))
    throw InvalidValue("pile.interface_friction_angle_deg", "(missing)",
                       fmt::format("given, in [0, 89] deg: the default 2/3 of the sand's friction "
                                   "angle needs one, and material \"{}\" has no friction angle",
                                   s.installation_material));
  require(s.displacement_step_D > 0.0, "solver.displacement_step_D", s.displacement_step_D, "> 0");
}

std::vector<ScenarioPhase> scenario_phases(const CentrifugeScenario& s) {
  using simulation::MpmPhaseRole;
  std::vector<ScenarioPhase> phases{{"initial-stress", MpmPhaseRole::initial_stress}};
  if (s.installation_D > 0.0) {
    const std::vector<double> stops = installation_stops_D(s);
    for (std::size_t k = 0; k + 1 < stops.size(); ++k)
      phases.push_back({"installation-to-" + depth_label(stops[k]), MpmPhaseRole::installation});
    phases.push_back({"installation", MpmPhaseRole::installation});
    if (s.relaxation) phases.push_back({"relaxation", MpmPhaseRole::relaxation});
  }
  if (s.load_test_D > 0.0) phases.push_back({"load-test", MpmPhaseRole::load_test});
  return phases;
}

std::vector<std::string> scenario_phase_names(const CentrifugeScenario& s) {
  std::vector<std::string> names;
  for (const ScenarioPhase& phase : scenario_phases(s)) names.push_back(phase.name);
  return names;
}

namespace {

// The grid of the scenario: the cell size of the fine zone, the sand and the container, and the
// fine band in y, from below the deepest tip to the top of the grid, with the sand surface on a
// grid line and at least two cells of graded grid below it.
struct ScenarioGrid {
  double h, H, R, band_bottom, top, fine_radius;
};

ScenarioGrid scenario_grid(const CentrifugeScenario& s) {
  const double D = s.pile_diameter;
  const double h = D / s.cells_per_D;
  const double H = s.sand_height();
  const double deepest = s.wished_in_place_D + s.installation_D;
  const int cells_above = static_cast<int>(std::ceil(s.headroom_D * s.cells_per_D - 1e-9));
  int cells_below =
      static_cast<int>(std::ceil((deepest + s.fine_depth_below_tip_D) * s.cells_per_D - 1e-9));
  cells_below = std::min(cells_below, static_cast<int>(std::floor(H / h + 1e-9)) - 2);
  return {h,
          H,
          s.container_radius(),
          H - cells_below * h,
          H + cells_above * h,
          std::round(s.fine_radius_D * s.cells_per_D) * h};
}

}  // namespace

namespace {

// A value rounded to 9 significant digits: the case's numbers are those a person would write in
// a case file (and mpm_case.toml, written from the case, shows them so).
double file_value(double value) {
  return with_significant_digits(value, 9);
}

}  // namespace

simulation::MpmCase centrifuge_case(const CentrifugeScenario& s, const std::string& source_name) {
  using namespace simulation;
  validate(s);
  const auto v = file_value;
  const double D = s.pile_diameter;
  const auto [h, H, R, band_bottom, top, fine_radius] = scenario_grid(s);

  MpmCase c;
  c.source = source_name;
  c.title = s.title;
  c.geometry = mpm::Geometry::axisymmetric;
  // Fine cells of size h near the axis (x) and from below the deepest tip to the top (y).
  auto graded = [&](double max, double band_min, double band_max) {
    MpmGridAxis axis;
    axis.graded = true;
    axis.min = 0.0;
    axis.max = v(max);
    axis.band_min = v(band_min);
    axis.band_max = v(band_max);
    axis.fine_spacing = v(h);
    axis.growth_ratio = v(s.growth_ratio);
    return axis;
  };
  c.x_axis = graded(R, 0.0, fine_radius);
  c.y_axis = graded(top, band_bottom, top);
  c.x_nodes = c.x_axis.nodes();
  c.y_nodes = c.y_axis.nodes();
  c.boundaries.fill(mpm::BoundaryCondition::free);
  c.boundaries[static_cast<std::size_t>(mpm::Side::right)] = mpm::BoundaryCondition::roller;
  c.boundaries[static_cast<std::size_t>(mpm::Side::bottom)] = mpm::BoundaryCondition::fixed;
  mpm::SolverSettings& solver = c.solver;
  solver.gravity = v(s.gravity);
  solver.gravity_multiplier = v(s.g_level);
  solver.threads = s.threads;
  solver.volumetric_smoothing = s.volumetric_smoothing;  // B-bar in the quasi-static analysis
  solver.geometry = c.geometry;
  c.analysis = s.analysis;
  const bool quasi_static = s.analysis == MpmAnalysis::quasi_static;
  if (quasi_static) {
    c.displacement_step = v(s.displacement_step_D * D);
    // The contact's normal force smoothed over a fraction of the particle size: without it the
    // quick case's installation stopped at 1.6 D (docs/centrifuge.md, "The quasi-static analysis").
    c.quasi_static.contact.smoothing = v(s.contact_smoothing);
    c.quasi_static.force_tolerance = v(s.force_tolerance);
    // A wandering sub-increment is given up without waiting for max_iterations:
    // docs/centrifuge.md, "Newton's tolerance".
    c.quasi_static.stall_iterations = s.stall_iterations;
    c.quasi_static.accept_tolerance = v(s.accept_tolerance);
    c.quasi_static.tangent_reuse = v(s.tangent_reuse);
    c.quasi_static.step_limit = v(s.newton_step_limit_cells);
    c.quasi_static.energy_tolerance =
        v(s.energy_tolerance.value_or(mpm::quasi_static::energy_tolerance_for(s.force_tolerance)));
    c.quasi_static.low_stress_stiffness = v(s.low_stress_stiffness);
    c.quasi_static.low_stress_pressure = v(s.low_stress_pressure_Pa);
    c.quasi_static.low_stress_use = s.low_stress_use;
    c.quasi_static.inside_body_weakness = v(s.inside_body_weakness);
  } else {  // the explicit analysis's own settings (the quasi-static case keeps the defaults)
    solver.mass_scaling = v(s.mass_scaling);
    solver.courant_number = v(s.courant_number);
    solver.flip_fraction = v(s.flip_fraction);
    solver.xpic_order = s.xpic_order;
    solver.local_damping = v(s.damping);
  }
  c.integrator = s.integrator;
  c.materials = s.materials;

  // The sand: one region, or the fine zone and the two rectangles around it.
  const MaterialSpec sand = scenario_material(s, s.installation_material);
  auto region = [&](const std::string& name, double x_min, double x_max, double y_min, double y_max,
                    int per_cell) {
    MpmRegion r;
    const int index = static_cast<int>(c.regions.size());
    r.name = name;
    r.source = source_name;
    r.key = fmt::format("region[{}]", index);
    r.fill.x_min = v(x_min);
    r.fill.x_max = v(x_max);
    r.fill.y_min = v(y_min);
    r.fill.y_max = v(y_max);
    r.fill.particles_per_cell_x = r.fill.particles_per_cell_y = per_cell;
    r.fill.density = v(s.sand_density());
    r.fill.material = index;
    r.material = sand;
    if (sand.is_hypoplastic()) {
      r.igs = named_igs(s.igs);
      r.igs_in_region = true;
      r.e0_at = parse_void_ratio_convention(s.e0_at, "e0_at");
    }  // other models: no intergranular strain, e0 at the initial stress
    r.initial_stress = MpmInitialStress::geostatic;
    r.K0 = v(scenario_K0(s));
    r.e0 = v(s.e0);
    c.models.push_back(make_model(r.material, r.igs, s.integrator));
    c.material_names.push_back(r.material.name);
    c.regions.push_back(std::move(r));
  };
  const int outside = s.particles_per_cell_outside;
  if (outside == s.particles_per_cell) {
    region("sand", 0.0, R, 0.0, H, s.particles_per_cell);
  } else {
    region("sand", 0.0, fine_radius, band_bottom, H, s.particles_per_cell);
    region("sand-beside", fine_radius, R, 0.0, H, outside);
    region("sand-below", 0.0, fine_radius, 0.0, band_bottom, outside);
  }

  MpmBody pile;
  pile.name = "pile";
  pile.key = "body[0]";
  pile.kind = MpmBodyKind::pile;
  pile.radius = v(s.pile_radius());
  pile.tip_y = v(s.initial_tip_y());
  pile.apex_angle = s.tip == "conical" ? v(s.apex_angle_deg) * kPi / 180.0 : kPi;
  pile.friction = std::tan(v(scenario_interface_friction_deg(s)) * kPi / 180.0);
  c.bodies.push_back(pile);

  // The phases, in the order and with the roles of scenario_phases.
  auto phase = [&](const ScenarioPhase& role, double duration, double record_time) {
    MpmPhase p;
    p.name = role.name;
    p.role = role.role;
    p.duration = v(duration);
    p.gravity_multiplier = solver.gravity_multiplier;
    p.local_damping = solver.local_damping;
    p.output_interval = p.duration;
    p.energy_interval = v(std::min(record_time, duration));
    p.body_motion.assign(c.bodies.size(), MpmBodyMotion{});
    return p;
  };
  auto move = [&](MpmPhase& p, double direction, const PileMotion& m) {
    p.body_motion[0].velocity = {0.0, v(direction * m.velocity)};
    p.body_motion[0].ramp = v(m.ramp);
  };
  auto stop = [](MpmPhase& p, const char* key, MpmStopQuantity quantity, double value) {
    p.stop_rules.push_back({key, quantity, 1, value});
    p.stop_body = 0;
  };
  const std::vector<ScenarioPhase> roles = scenario_phases(s);
  std::size_t next = 0;
  // Explicit: records through the K0 phase while the sand settles; quasi-static: one load step
  // to equilibrium under N g, recorded at its end.
  MpmPhase initial = phase(roles[next++], s.initial_stress_time,
                           quasi_static ? s.initial_stress_time : s.initial_stress_time / 20.0);
  initial.kind = MpmPhaseKind::geostatic;
  if (!quasi_static) initial.local_damping = v(s.initial_stress_damping);
  c.phases.push_back(initial);
  const double record = s.record_interval_D * D;
  if (s.installation_D > 0.0) {
    const std::vector<double> stops = installation_stops_D(s);
    double from = s.wished_in_place_D;
    for (std::size_t k = 0; k < stops.size(); ++k) {
      MpmPhase p = phase(roles[next++], phase_duration((stops[k] - from) * D, s.jacking),
                         record / s.jacking.velocity);
      stop(p, "stop_displacement_y_m", MpmStopQuantity::displacement,
           v(-(stops[k] - s.wished_in_place_D) * D));
      p.checkpoint = k + 1 == stops.size();
      move(p, -1.0, s.jacking);
      c.phases.push_back(std::move(p));
      from = stops[k];
    }
    if (s.relaxation) {
      const double travel = s.relaxation_max_D * D;
      MpmPhase p = phase(roles[next++], phase_duration(travel, s.relaxation_motion),
                         0.1 * record / s.relaxation_motion.velocity);
      // In the order the case file's reader takes them: displacement rules before force rules.
      stop(p, "stop_phase_displacement_y_m", MpmStopQuantity::phase_displacement, v(travel));
      stop(p, "stop_force_y_below_N", MpmStopQuantity::force_below, 0.0);
      // The quasi-static analysis finds the zero of the head force by bisection of a load step.
      if (!quasi_static) p.stop_force_averaging = v(s.relaxation_force_averaging);
      move(p, 1.0, s.relaxation_motion);
      c.phases.push_back(std::move(p));
    }
  }
  if (s.load_test_D > 0.0) {
    const double travel = s.load_test_D * D;
    MpmPhase p = phase(roles[next++], phase_duration(travel, s.load_test_motion),
                       0.1 * record / s.load_test_motion.velocity);
    stop(p, "stop_phase_displacement_y_m", MpmStopQuantity::phase_displacement, v(-travel));
    move(p, -1.0, s.load_test_motion);
    if (!s.load_test_material.empty() && s.load_test_material != s.installation_material) {
      const MaterialSpec set = scenario_material(s, s.load_test_material);
      for (std::size_t i = 0; i < c.regions.size(); ++i)
        p.material_changes.push_back(
            {static_cast<int>(i), set.name, make_model(set, c.regions[i].igs, s.integrator)});
    }
    c.phases.push_back(std::move(p));
  }
  c.solver.validate();
  return c;
}

}  // namespace pilempm::scenario
