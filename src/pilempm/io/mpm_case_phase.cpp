// The [[phase]] tables of MPM case files: see mpm_case.hpp and docs/mpm-case-files.md.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <optional>
#include <utility>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/io/mpm_case_detail.hpp"
#include "pilempm/simulation/run_loop.hpp"

namespace pilempm::mpm_case_detail {

using namespace simulation;

namespace {

// The keys of a sub-table whose keys are names (of bodies, of materials), in source order.
std::vector<std::string> table_keys(const toml::node& node) {
  std::vector<std::pair<long, std::string>> keys;
  if (const toml::table* table = node.as_table())
    for (auto&& [key, value] : *table)
      keys.emplace_back(static_cast<long>(value.source().begin.line), std::string(key.str()));
  std::stable_sort(keys.begin(), keys.end());
  std::vector<std::string> names;
  for (auto& key : keys) names.push_back(std::move(key.second));
  return names;
}

struct StopKey {
  const char* key;
  MpmStopQuantity quantity;
  int component;
};
const StopKey kStopKeys[] = {
    {"stop_displacement_x_m", MpmStopQuantity::displacement, 0},
    {"stop_displacement_y_m", MpmStopQuantity::displacement, 1},
    {"stop_phase_displacement_x_m", MpmStopQuantity::phase_displacement, 0},
    {"stop_phase_displacement_y_m", MpmStopQuantity::phase_displacement, 1},
    {"stop_force_x_below_N", MpmStopQuantity::force_below, 0},
    {"stop_force_y_below_N", MpmStopQuantity::force_below, 1},
    {"stop_force_x_above_N", MpmStopQuantity::force_above, 0},
    {"stop_force_y_above_N", MpmStopQuantity::force_above, 1},
};

// [phase.body.NAME] tables: the bodies' motion in the phase (at rest when absent).
void read_body_motions(TableReader& t, const MpmCase& c, MpmPhase& p) {
  p.body_motion.assign(c.bodies.size(), MpmBodyMotion{});
  const toml::node* node = t.node("body");
  if (node == nullptr) return;
  TableReader bodies = *t.table("body");
  std::vector<std::string> names;
  for (const MpmBody& b : c.bodies) names.push_back(b.name);
  for (const std::string& name : table_keys(*node)) {
    const auto at = std::find(names.begin(), names.end(), name);
    if (at == names.end())
      throw bodies.error(name, fmt::format("unknown body: must be the name of a [[body]], one of "
                                           "{}",
                                           quoted_names(names)));
    const std::size_t index = static_cast<std::size_t>(at - names.begin());
    std::optional<TableReader> motion = bodies.table(name);
    MpmBodyMotion& m = p.body_motion[index];
    if (c.bodies[index].kind == MpmBodyKind::pile && motion->contains("velocity_x_m_per_s"))
      throw motion->error("velocity_x_m_per_s",
                          "not allowed: a pile moves along the axis (y) only");
    m.velocity = {motion->number_or("velocity_x_m_per_s", 0.0, kVelocityRange),
                  motion->number_or("velocity_y_m_per_s", 0.0, kVelocityRange)};
    m.ramp = motion->number_or("ramp_s", 0.0, NumberRange::non_negative());
    motion->check_no_unknown_keys();
  }
  bodies.check_no_unknown_keys();
}

// The stop rules of a phase and the body they watch.
void read_stop_rules(TableReader& t, const MpmCase& c, MpmPhase& p) {
  std::vector<std::string> names;
  for (const MpmBody& b : c.bodies) names.push_back(b.name);
  for (const StopKey& k : kStopKeys) {
    const std::optional<double> value = t.optional_number(k.key, NumberRange::any());
    if (!value) continue;
    if (k.quantity == MpmStopQuantity::phase_displacement && *value == 0.0)
      throw t.error(k.key, "must be a non-zero displacement [m] (its sign gives the direction)");
    p.stop_rules.push_back({k.key, k.quantity, k.component, *value});
  }
  if (t.contains("stop_force_averaging_s")) {
    const bool force_rule =
        std::any_of(p.stop_rules.begin(), p.stop_rules.end(), [](const MpmStopRule& r) {
          return r.quantity == MpmStopQuantity::force_below ||
                 r.quantity == MpmStopQuantity::force_above;
        });
    if (!force_rule)
      throw t.error("stop_force_averaging_s",
                    "not allowed without a force stop rule (stop_force_y_below_N, ...)");
    p.stop_force_averaging = t.number("stop_force_averaging_s", NumberRange::non_negative());
  }
  const std::optional<std::string> body = t.optional_string("stop_body");
  if (p.stop_rules.empty()) {
    if (body)
      throw t.error("stop_body",
                    "not allowed without a stop rule (stop_displacement_y_m, "
                    "stop_force_y_below_N, ...)");
    return;
  }
  const std::string& first = p.stop_rules.front().key;
  if (c.bodies.empty())
    throw t.error(first,
                  "not allowed: a stop rule watches a rigid body, and the case has no "
                  "[[body]]");
  if (body) {
    const auto at = std::find(names.begin(), names.end(), *body);
    if (at == names.end())
      throw t.error("stop_body", fmt::format("unknown body: must be the name of a [[body]], one "
                                             "of {}",
                                             quoted_names(names)));
    p.stop_body = static_cast<int>(at - names.begin());
  } else if (c.bodies.size() == 1) {
    p.stop_body = 0;
  } else {
    throw t.missing("stop_body",
                    fmt::format("the body the stop rules watch, one of {}", quoted_names(names)));
  }
  if (c.bodies[static_cast<std::size_t>(p.stop_body)].kind == MpmBodyKind::pile)
    for (const MpmStopRule& rule : p.stop_rules)
      if (rule.component == 0)
        throw t.error(rule.key,
                      "not allowed for a pile: it moves along the axis only and its "
                      "radial forces cancel around it; use the _y_ rule");
}

// [phase.materials]: "role" = "new set" for the regions whose material is "role".
void read_material_changes(TableReader& t, const MpmCase& c, const MaterialCatalog& catalog,
                           MpmPhase& p) {
  const toml::node* node = t.node("materials");
  if (node == nullptr) return;
  TableReader materials = *t.table("materials");
  std::vector<std::string> roles;
  for (const MpmRegion& r : c.regions)
    if (std::find(roles.begin(), roles.end(), r.material.name) == roles.end())
      roles.push_back(r.material.name);
  for (const std::string& role : table_keys(*node)) {
    if (std::find(roles.begin(), roles.end(), role) == roles.end())
      throw materials.error(role, fmt::format("unknown: the key must be a material that a "
                                              "[[region]] names, one of {}",
                                              quoted_names(roles)));
    const std::string name = materials.string(role);
    const MaterialSpec* spec = catalog.find(name);
    if (spec == nullptr)
      throw materials.error(role, fmt::format("unknown: must be a [[material]] name or a "
                                              "built-in set, one of {}",
                                              fmt::join(catalog.names(), ", ")));
    for (std::size_t i = 0; i < c.regions.size(); ++i) {
      const MpmRegion& r = c.regions[i];
      if (r.material.name != role) continue;
      if (spec->model != r.material.model)
        throw materials.error(role, fmt::format("must be a {} material like \"{}\" (the "
                                                "particles keep their state), not {}",
                                                r.material.model, role, spec->model));
      const HypoplasticMaterial* hypoplastic = spec->parameters_as<HypoplasticMaterial>();
      const std::optional<IgsChoice> igs =
          r.igs_in_region || !(hypoplastic && hypoplastic->igs) ? r.igs : hypoplastic->igs;
      try {
        p.material_changes.push_back(
            {static_cast<int>(i), name, make_model(*spec, igs, catalog.integrator())});
      } catch (const InvalidValue& e) {
        throw materials.error(role,
                              fmt::format("{} = {}: must be {}", e.key(), e.value(), e.allowed()));
      }
    }
  }
  materials.check_no_unknown_keys();
}

}  // namespace

MpmPhase read_phase(TableReader& t, const MpmCase& c, const MaterialCatalog& catalog, int index) {
  const mpm::SolverSettings& solver = c.solver;
  MpmPhase p;
  p.name = t.name_or("name", fmt::format("phase{}", index + 1));
  if (t.optional_choice("kind", {"standard", "geostatic"}).value_or("standard") == "geostatic") {
    p.kind = MpmPhaseKind::geostatic;
    if (std::none_of(c.regions.begin(), c.regions.end(), [](const MpmRegion& r) {
          return r.initial_stress == MpmInitialStress::geostatic;
        }))
      throw t.error("kind",
                    "not allowed: a geostatic phase resets the regions with "
                    "initial_stress = \"geostatic\", and there are none");
  }
  if (auto role = t.optional_choice(
          "role", {"initial-stress", "installation", "relaxation", "load-test"})) {
    for (MpmPhaseRole r : {MpmPhaseRole::initial_stress, MpmPhaseRole::installation,
                           MpmPhaseRole::relaxation, MpmPhaseRole::load_test})
      if (to_string(r) == *role) p.role = r;
  }
  p.duration = t.number("duration_s", NumberRange::positive());
  p.gravity_multiplier =
      t.number_or("gravity_multiplier", solver.gravity_multiplier, NumberRange::non_negative());
  if (c.analysis == MpmAnalysis::quasi_static) {
    if (t.contains("local_damping"))
      throw t.error("local_damping",
                    "applies to analysis = \"explicit\" only (the quasi-static analysis has no "
                    "inertia to damp)");
    p.displacement_step = t.number_or("displacement_step_m", 0.0, NumberRange::positive());
  } else if (t.contains("displacement_step_m")) {
    throw t.error("displacement_step_m",
                  "applies to analysis = \"quasi-static\" only (set [solver] analysis)");
  }
  p.local_damping = t.number_or("local_damping", solver.local_damping, {0.0, 1.0, false, true});
  // At most kMaxSeriesTimes output or record times in a phase: the run loop steps to each.
  const NumberRange interval = NumberRange::closed(p.duration / kMaxSeriesTimes, p.duration);
  p.output_interval = t.number_or("output_interval_s", p.duration, interval);
  p.energy_interval = t.number_or("energy_interval_s", p.output_interval / 10.0, interval);
  p.traction_multiplier = t.number_or("traction_multiplier", 1.0, NumberRange::any());
  p.checkpoint = t.boolean_or("checkpoint", true);
  read_body_motions(t, c, p);
  read_stop_rules(t, c, p);
  read_material_changes(t, c, catalog, p);
  t.check_no_unknown_keys();
  return p;
}

}  // namespace pilempm::mpm_case_detail
