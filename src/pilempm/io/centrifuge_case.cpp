#include "pilempm/io/centrifuge_case.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "pilempm/io/material_reader.hpp"
#include "pilempm/io/mpm_case.hpp"
#include "pilempm/io/mpm_case_writer.hpp"
#include "pilempm/io/toml_reader.hpp"

namespace pilempm {

using namespace scenario;

namespace {

PileMotion read_motion(TableReader& t, PileMotion motion) {
  motion.velocity = t.number_or("velocity_m_per_s", motion.velocity, NumberRange::positive());
  motion.ramp = t.number_or("ramp_s", motion.ramp, NumberRange::non_negative());
  return motion;
}

}  // namespace

CentrifugeScenario read_centrifuge_case_text(std::string_view text, const std::string& source_name,
                                             std::optional<simulation::MpmAnalysis> analysis) {
  const toml::table document = parse_toml_text(text, source_name);
  TableReader root(document, source_name, "");
  CentrifugeScenario s;
  s.title = root.optional_string("title").value_or(s.title);

  // The analysis first: it decides which keys of the other tables apply, and the integrator's
  // defaults.
  if (auto t = root.table("solver"))
    if (t->optional_choice("analysis", {"explicit", "quasi-static"}).value_or("explicit") ==
        "quasi-static")
      s.analysis = simulation::MpmAnalysis::quasi_static;
  if (analysis) s.analysis = *analysis;
  const bool quasi_static = s.analysis == simulation::MpmAnalysis::quasi_static;
  // How a message names where the analysis was chosen.
  const std::string chosen_by = analysis ? "set by --analysis" : "set by [solver] analysis";

  // Then the materials: the sand may name one of them.
  MaterialCatalog catalog;
  catalog.read(root, simulation::default_integrator(s.analysis));
  for (const std::string& name : catalog.names())
    if (const MaterialSpec* material = catalog.find(name); !material->builtin)
      s.materials.push_back(*material);
  s.integrator = catalog.integrator();
  // A key of the explicit analysis in a quasi-static case.
  auto refuse_explicit = [&](TableReader& t, const char* key) {
    if (quasi_static && t.contains(key))
      throw t.error(key,
                    fmt::format("applies to analysis = \"explicit\" only (this case runs "
                                "analysis = \"quasi-static\", {}, which has no inertia, damping "
                                "or force averaging)",
                                chosen_by));
  };

  if (auto t = root.table("test")) {
    s.pile_diameter =
        t->number_or("pile_diameter_mm", s.pile_diameter * 1e3, NumberRange::positive()) * 1e-3;
    s.g_level = t->number_or("g_level", s.g_level, NumberRange::closed(1.0, 1000.0));
    s.gravity = t->number_or("gravity_m_per_s2", s.gravity, NumberRange::positive());
    s.container_radius_D =
        t->number_or("container_radius_D", s.container_radius_D, NumberRange::closed(2.0, 1000.0));
    s.sand_height_D =
        t->number_or("sand_height_D", s.sand_height_D, NumberRange::closed(2.0, 1000.0));
    t->check_no_unknown_keys();
  }

  if (auto t = root.table("sand")) {
    s.installation_material = t->optional_string("material").value_or(s.installation_material);
    const MaterialSpec* material = catalog.find(s.installation_material);
    if (material == nullptr)
      throw t->error("material", fmt::format("unknown: must be a built-in set or a [[material]] "
                                             "of the file ({})",
                                             fmt::join(catalog.names(), ", ")));
    const bool hypoplastic = material->is_hypoplastic();
    s.material_phi_c_deg = material_friction_angle_deg(*material);
    if (auto name = t->optional_string("load_test_material")) {
      const MaterialSpec* other = catalog.find(*name);
      if (other == nullptr)
        throw t->error("load_test_material",
                       fmt::format("unknown: must be a built-in set or a [[material]] of the "
                                   "file ({})",
                                   fmt::join(catalog.names(), ", ")));
      // The MPM-4 switch: each point keeps its stress, void ratio and intergranular strain.
      if (!hypoplastic || !other->is_hypoplastic())
        throw t->error("load_test_material",
                       fmt::format("not allowed: the load-test set replaces one hypoplastic set "
                                   "by another (each point keeps its stress, void ratio and "
                                   "intergranular strain), and \"{}\" is {}, \"{}\" is {}",
                                   s.installation_material, material->model, *name, other->model));
      s.load_test_material = *name;
    }
    if (hypoplastic) {
      s.igs = t->optional_choice("igs", igs_choice_names()).value_or(s.igs);
      s.e0 = t->number("e0", NumberRange::open(0.0, 5.0));
      s.e0_at = t->choice("e0_at", {"initial-stress", "zero-pressure"});
    } else {
      // The void ratio every model carries (the default density, the fields); the intergranular
      // strain and Bauer's scaling of e0 belong to the hypoplastic model.
      for (const char* key : {"igs", "e0_at"})
        if (t->contains(key))
          throw t->error(key, fmt::format("not allowed: it belongs to the hypoplastic model, and "
                                          "material \"{}\" is {} (e0 is the void ratio at the "
                                          "initial stress)",
                                          s.installation_material, material->model));
      s.e0 = t->number("e0", NumberRange::open(0.0, 5.0));
      s.e0_at = "initial-stress";
    }
    s.density = t->optional_number("density_kg_per_m3", NumberRange::positive());
    s.grain_density =
        t->number_or("grain_density_kg_per_m3", s.grain_density, NumberRange::positive());
    s.K0 = t->optional_number("K0", NumberRange::open(0.0, 5.0));
    t->check_no_unknown_keys();
  } else {
    throw root.missing("sand",
                       "[sand] with e0 and e0_at (\"initial-stress\" or \"zero-pressure\")");
  }

  if (auto t = root.table("pile")) {
    s.tip = t->optional_choice("tip", {"conical", "flat"}).value_or(s.tip);
    if (s.tip == "conical")
      s.apex_angle_deg =
          t->number_or("apex_angle_deg", s.apex_angle_deg, NumberRange::open(0, 180));
    s.interface_friction_angle_deg =
        t->optional_number("interface_friction_angle_deg", NumberRange::closed(0.0, 89.0));
    t->check_no_unknown_keys();
  }

  if (auto t = root.table("initial_stress")) {
    refuse_explicit(*t, "local_damping");
    s.initial_stress_time =
        t->number_or("duration_s", s.initial_stress_time, NumberRange::positive());
    s.initial_stress_damping =
        t->number_or("local_damping", s.initial_stress_damping, NumberRange{0.0, 1.0, false, true});
    t->check_no_unknown_keys();
  }

  if (auto t = root.table("installation")) {
    s.wished_in_place_D =
        t->number_or("wished_in_place_D", s.wished_in_place_D, NumberRange::non_negative());
    s.installation_D = t->number_or("depth_D", s.installation_D, NumberRange::non_negative());
    s.jacking = read_motion(*t, s.jacking);
    if (t->contains("snapshot_depths_D"))
      s.snapshot_depths_D =
          t->number_array("snapshot_depths_D", NumberRange::non_negative(), 0, 100, true);
    t->check_no_unknown_keys();
  }

  if (auto t = root.table("relaxation")) {
    refuse_explicit(*t, "force_averaging_s");
    s.relaxation = t->boolean_or("enabled", s.relaxation);
    s.relaxation_motion = read_motion(*t, s.relaxation_motion);
    s.relaxation_max_D = t->number_or("max_travel_D", s.relaxation_max_D, NumberRange::positive());
    s.relaxation_force_averaging = t->number_or("force_averaging_s", s.relaxation_force_averaging,
                                                NumberRange::non_negative());
    t->check_no_unknown_keys();
  }

  if (auto t = root.table("load_test")) {
    s.load_test_D = t->number_or("displacement_D", s.load_test_D, NumberRange::closed(0.0, 10.0));
    s.load_test_motion = read_motion(*t, s.load_test_motion);
    t->check_no_unknown_keys();
  }

  if (auto t = root.table("mesh")) {
    s.cells_per_D = t->number_or("cells_per_D", s.cells_per_D, NumberRange::closed(1.0, 64.0));
    s.fine_radius_D = t->number_or("fine_radius_D", s.fine_radius_D, NumberRange::at_least(1.0));
    s.fine_depth_below_tip_D = t->number_or("fine_depth_below_tip_D", s.fine_depth_below_tip_D,
                                            NumberRange::non_negative());
    s.headroom_D = t->number_or("headroom_D", s.headroom_D, NumberRange::closed(0.5, 100.0));
    s.growth_ratio = t->number_or("growth_ratio", s.growth_ratio, NumberRange::closed(1.0, 2.0));
    s.particles_per_cell = t->integer_or("particles_per_cell", s.particles_per_cell, 1, 8);
    s.particles_per_cell_outside =
        t->integer_or("particles_per_cell_outside", s.particles_per_cell_outside, 1, 8);
    t->check_no_unknown_keys();
  }

  if (auto t = root.table("solver")) {
    (void)t->optional_choice("analysis", {"explicit", "quasi-static"});  // read above
    for (const char* key :
         {"mass_scaling", "courant_number", "flip_fraction", "xpic_order", "local_damping"})
      refuse_explicit(*t, key);
    for (const char* key : {"displacement_step_D", "contact_smoothing", "force_tolerance",
                            "energy_tolerance", "accept_tolerance", "stall_iterations",
                            "tangent_reuse", "newton_step_limit_cells", "low_stress_stiffness",
                            "low_stress_pressure_Pa", "low_stress_use", "inside_body_weakness"})
      if (!quasi_static && t->contains(key))
        throw t->error(key, analysis ? "applies to analysis = \"quasi-static\" only (this case "
                                       "runs analysis = \"explicit\", set by --analysis)"
                                     : "applies to analysis = \"quasi-static\" only (set [solver] "
                                       "analysis)");
    s.displacement_step_D =
        t->number_or("displacement_step_D", s.displacement_step_D, NumberRange::closed(1e-4, 1.0));
    s.contact_smoothing =
        t->number_or("contact_smoothing", s.contact_smoothing, NumberRange::closed(0.0, 1.0));
    s.force_tolerance =
        t->number_or("force_tolerance", s.force_tolerance, NumberRange::closed(1e-12, 1e-3));
    if (t->contains("energy_tolerance"))
      s.energy_tolerance = t->number_or("energy_tolerance", 0.0, NumberRange::closed(1e-24, 1e-2));
    s.accept_tolerance =
        t->number_or("accept_tolerance", s.accept_tolerance, NumberRange::closed(0.0, 0.1));
    s.stall_iterations = t->integer_or("stall_iterations", s.stall_iterations, 0, 1000);
    s.tangent_reuse = t->number_or("tangent_reuse", s.tangent_reuse, NumberRange::closed(0.0, 0.5));
    s.newton_step_limit_cells = t->number_or("newton_step_limit_cells", s.newton_step_limit_cells,
                                             NumberRange::closed(0.0, 100.0));
    s.low_stress_stiffness = t->number_or("low_stress_stiffness", s.low_stress_stiffness,
                                          NumberRange::closed(0.0, 10.0));
    s.low_stress_pressure_Pa = t->number_or("low_stress_pressure_Pa", s.low_stress_pressure_Pa,
                                            NumberRange::left_open(0.0, 1.0e7));
    if (auto use = t->optional_choice("low_stress_use", {"last_resort", "every_step"}))
      s.low_stress_use = *use == "every_step" ? mpm::quasi_static::StabilisationUse::every_step
                                              : mpm::quasi_static::StabilisationUse::last_resort;
    s.inside_body_weakness =
        t->number_or("inside_body_weakness", s.inside_body_weakness, NumberRange::closed(0.0, 1.0));
    s.mass_scaling = t->number_or("mass_scaling", s.mass_scaling, NumberRange::at_least(1.0));
    s.courant_number =
        t->number_or("courant_number", s.courant_number, NumberRange::left_open(0.0, 1.0));
    s.flip_fraction = t->number_or("flip_fraction", s.flip_fraction, NumberRange::closed(0.0, 1.0));
    s.xpic_order = t->integer_or("xpic_order", s.xpic_order, 1, 8);
    s.threads = t->integer_or("threads", s.threads, 0, 1024);
    s.volumetric_smoothing = t->boolean_or("volumetric_smoothing", s.volumetric_smoothing);
    s.damping = t->number_or("local_damping", s.damping, NumberRange{0.0, 1.0, false, true});
    t->check_no_unknown_keys();
  }

  if (auto t = root.table("output")) {
    s.record_interval_D =
        t->number_or("record_interval_D", s.record_interval_D, NumberRange::left_open(0.0, 1.0));
    t->check_no_unknown_keys();
  }
  root.check_no_unknown_keys();

  try {
    validate(s);
  } catch (const InvalidValue& e) {
    // The key is "table.key": point at its line when the file has it.
    const std::string& key = e.key();
    const auto dot = key.find('.');
    long line = 0;
    if (dot != std::string::npos)
      if (auto t = root.table(key.substr(0, dot))) line = t->line_of(key.substr(dot + 1));
    throw InputError(source_name, line, key, e.value(), e.allowed());
  }
  // Everything `centrifuge run` checks, checked now: the MPM case the scenario becomes is read as
  // the run will read it. What it rejects comes from a combination of this file's values; the
  // message names this file (not the generated mpm_case.toml the user never wrote).
  try {
    (void)centrifuge_to_mpm_case(s, "mpm_case.toml");
  } catch (const InputError& e) {
    throw InputError(source_name, 0, "", "",
                     fmt::format("the values of this file give an MPM case that is not valid "
                                 "(change the values that set it): {}",
                                 e.what()));
  }
  return s;
}

CentrifugeScenario read_centrifuge_case(const std::filesystem::path& path,
                                        std::optional<simulation::MpmAnalysis> analysis) {
  return read_centrifuge_case_text(read_case_text(path), path.string(), analysis);
}

std::string centrifuge_mpm_case_text(const simulation::MpmCase& c) {
  return mpm_case_text(
      c, {"Written by pilempm from a centrifuge scenario (docs/centrifuge.md); `pilempm mpm run`",
          "runs it as the centrifuge run ran it. The left side is the axis, the right one the",
          "container wall (smooth), the bottom its floor; the sand regions tile the container, the",
          "pile is wished in place."});
}

simulation::MpmCase centrifuge_to_mpm_case(const CentrifugeScenario& scenario,
                                           const std::string& source_name) {
  std::string text;
  try {
    text = centrifuge_mpm_case_text(centrifuge_case(scenario, source_name));
  } catch (const InvalidValue& e) {
    throw InputError(source_name, 0, e.key(), e.value(), e.allowed());
  }
  return read_mpm_case_text(text, source_name);
}

}  // namespace pilempm
