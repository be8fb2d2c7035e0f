// MPM case files: see mpm_case.hpp and docs/mpm-case-files.md.
#include "pilempm/io/mpm_case.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <utility>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/core/tensor.hpp"
#include "pilempm/io/material_reader.hpp"
#include "pilempm/io/mpm_case_detail.hpp"
#include "pilempm/io/toml_reader.hpp"
#include "pilempm/simulation/run_loop.hpp"

namespace pilempm {

using namespace simulation;
using mpm_case_detail::kVelocityRange;
using mpm_case_detail::quoted_names;
using mpm_case_detail::read_phase;

namespace {

constexpr double kKPa = 1.0e3;
constexpr int kMaxCells = 100000;
constexpr int kMaxParticlesPerCell = 16;
constexpr int kMaxThreads = 1024;

const std::vector<std::string> kBoundaryNames = {"free", "roller", "fixed"};
const std::vector<std::string> kConventions = {"initial-stress", "zero-pressure"};

mpm::BoundaryCondition parse_boundary(const std::string& text) {
  if (text == "roller") return mpm::BoundaryCondition::roller;
  if (text == "fixed") return mpm::BoundaryCondition::fixed;
  return mpm::BoundaryCondition::free;
}

// One axis of [grid]: [grid.x] or [grid.y], with its nodes.
MpmGridAxis read_axis(TableReader& grid, std::string_view key, std::vector<double>& nodes) {
  std::optional<TableReader> axis = grid.table(key);
  if (!axis)
    throw grid.missing(key, fmt::format("the {} axis: a table with spacing = \"uniform\" or "
                                        "\"graded\", min_m, max_m and its cells",
                                        key));
  const std::string spacing = axis->choice("spacing", {"uniform", "graded"});
  axis->declare({"min_m", "max_m", "cells", "band_min_m", "band_max_m", "fine_spacing_m",
                 "growth_ratio", "max_spacing_m"});
  MpmGridAxis a;
  a.min = axis->number("min_m", NumberRange::any());
  a.max = axis->number("max_m", NumberRange::above(a.min));
  try {
    if (spacing == "uniform") {
      a.cells = axis->integer("cells", 1, kMaxCells);
      axis->check_no_unknown_keys();
      nodes = a.nodes();
      return a;
    }
    a.graded = true;
    a.band_min = axis->number("band_min_m", NumberRange::closed(a.min, a.max));
    a.band_max = axis->number("band_max_m", NumberRange::left_open(a.band_min, a.max));
    a.fine_spacing = axis->number("fine_spacing_m", NumberRange::positive());
    a.growth_ratio = axis->number("growth_ratio", NumberRange::closed(1.0, 10.0));
    a.max_spacing =
        axis->number_or("max_spacing_m", NumberRange::kInf, NumberRange::at_least(a.fine_spacing));
    axis->check_no_unknown_keys();
    if ((a.max - a.min) / a.fine_spacing > kMaxCells)
      throw axis->error("fine_spacing_m", fmt::format("too small: more than {} cells", kMaxCells));
    nodes = a.nodes();
    return a;
  } catch (const InvalidValue& e) {
    throw axis->error_from(e);
  }
}

// The keys of [solver] that only one analysis reads.
const std::vector<std::string> kExplicitOnlyKeys = {
    "scheme",       "flip_fraction",  "xpic_order",        "local_damping",
    "mass_scaling", "courant_number", "fixed_time_step_s", "contact"};
const std::vector<std::string> kQuasiStaticOnlyKeys = {"displacement_step_m",
                                                       "force_tolerance",
                                                       "energy_tolerance",
                                                       "max_iterations",
                                                       "max_cuts",
                                                       "accept_tolerance",
                                                       "accept_after_iterations",
                                                       "stall_iterations",
                                                       "tangent_reuse",
                                                       "strain_increment",
                                                       "linear_solver",
                                                       "contact_penalty_factor",
                                                       "newton_step_limit_cells",
                                                       "contact_vertex_radius_cells",
                                                       "contact_smoothing",
                                                       "low_stress_stiffness",
                                                       "low_stress_use",
                                                       "low_stress_pressure_Pa",
                                                       "inside_body_weakness"};

// The names of [solver] linear_solver, fastest first.
std::vector<std::string> linear_solver_names() {
  std::vector<std::string> names;
  for (const auto kind : mpm::quasi_static::kLinearSolverKinds)
    names.push_back(mpm::quasi_static::to_string(kind));
  return names;
}

// [solver]: the analysis and its settings; a key of the other analysis is an error.
void read_solver(std::optional<TableReader> solver, MpmCase& c) {
  mpm::SolverSettings& s = c.solver;
  if (!solver) return;
  if (solver->optional_choice("analysis", {"explicit", "quasi-static"}).value_or("explicit") ==
      "quasi-static")
    c.analysis = MpmAnalysis::quasi_static;
  const bool quasi_static = c.analysis == MpmAnalysis::quasi_static;
  for (const std::string& key : quasi_static ? kExplicitOnlyKeys : kQuasiStaticOnlyKeys)
    if (solver->contains(key))
      throw solver->error(
          key, fmt::format("applies to analysis = \"{}\" only (this case runs "
                           "analysis = \"{}\")",
                           quasi_static ? "explicit" : "quasi-static", to_string(c.analysis)));
  if (auto scheme = solver->optional_choice("scheme", {"musl", "usl"}))
    s.scheme = *scheme == "usl" ? mpm::UpdateScheme::usl : mpm::UpdateScheme::musl;
  if (auto shape = solver->optional_choice("shape_function", {"linear", "ugimp", "cpgimp"}))
    s.shape_function = *shape == "linear"  ? mpm::ShapeFunction::linear
                       : *shape == "ugimp" ? mpm::ShapeFunction::ugimp
                                           : mpm::ShapeFunction::cpgimp;
  if (auto contact = solver->optional_choice("contact", {"nodes", "surface"}))
    s.contact = *contact == "surface" ? mpm::ContactScheme::surface : mpm::ContactScheme::nodes;
  s.flip_fraction = solver->number_or("flip_fraction", s.flip_fraction, NumberRange::closed(0, 1));
  s.xpic_order = solver->integer_or("xpic_order", s.xpic_order, 1, 8);
  s.gravity = solver->number_or("gravity_m_per_s2", s.gravity, NumberRange::non_negative());
  s.gravity_multiplier =
      solver->number_or("gravity_multiplier", s.gravity_multiplier, NumberRange::non_negative());
  s.local_damping = solver->number_or("local_damping", s.local_damping, {0.0, 1.0, false, true});
  s.mass_scaling = solver->number_or("mass_scaling", s.mass_scaling, NumberRange::at_least(1.0));
  s.courant_number =
      solver->number_or("courant_number", s.courant_number, NumberRange::left_open(0.0, 1.0));
  s.fixed_time_step =
      solver->number_or("fixed_time_step_s", s.fixed_time_step, NumberRange::non_negative());
  s.threads = solver->integer_or("threads", s.threads, 0, kMaxThreads);
  s.volumetric_smoothing = solver->boolean_or("volumetric_smoothing", s.volumetric_smoothing);
  mpm::quasi_static::Settings& q = c.quasi_static;
  c.displacement_step = solver->number_or("displacement_step_m", 0.0, NumberRange::positive());
  q.force_tolerance =
      solver->number_or("force_tolerance", q.force_tolerance, NumberRange::closed(1e-12, 1e-1));
  // The energy norm falls about as the square of the residual's: by default the pair of the
  // library's defaults (1e-6, 1e-10) carried to a force tolerance given.
  if (solver->contains("force_tolerance"))
    q.energy_tolerance = mpm::quasi_static::energy_tolerance_for(q.force_tolerance);
  q.energy_tolerance =
      solver->number_or("energy_tolerance", q.energy_tolerance, NumberRange::closed(1e-24, 1.0));
  q.max_iterations = solver->integer_or("max_iterations", q.max_iterations, 1, 1000);
  q.max_cuts = solver->integer_or("max_cuts", q.max_cuts, 0, 30);
  q.accept_tolerance =
      solver->number_or("accept_tolerance", q.accept_tolerance, NumberRange::closed(0.0, 0.1));
  q.accept_after = solver->integer_or("accept_after_iterations", q.accept_after, 0, 1000);
  q.stall_iterations = solver->integer_or("stall_iterations", q.stall_iterations, 0, 1000);
  q.tangent_reuse =
      solver->number_or("tangent_reuse", q.tangent_reuse, NumberRange::closed(0.0, 0.5));
  if (auto measure = solver->optional_choice("strain_increment", {"midpoint", "start"}))
    q.midpoint_strain = *measure == "midpoint";
  if (auto linear = solver->optional_choice("linear_solver", linear_solver_names())) {
    q.linear_solver = *mpm::quasi_static::linear_solver_from_string(*linear);
    if (!mpm::quasi_static::linear_solver_available(q.linear_solver))
      throw solver->error(
          "linear_solver",
          fmt::format("{}: this build has no {} (use {})", *linear, *linear,
                      mpm::quasi_static::to_string(mpm::quasi_static::default_linear_solver())));
  }
  q.contact.penalty_factor = solver->number_or("contact_penalty_factor", q.contact.penalty_factor,
                                               NumberRange::closed(1e-3, 1e3));
  q.step_limit =
      solver->number_or("newton_step_limit_cells", q.step_limit, NumberRange::closed(0.0, 100.0));
  q.contact.vertex_radius = solver->number_or(
      "contact_vertex_radius_cells", q.contact.vertex_radius, NumberRange::closed(0.0, 2.0));
  q.contact.smoothing =
      solver->number_or("contact_smoothing", q.contact.smoothing, NumberRange::closed(0.0, 1.0));
  q.low_stress_stiffness = solver->number_or("low_stress_stiffness", q.low_stress_stiffness,
                                             NumberRange::closed(0.0, 10.0));
  q.low_stress_pressure = solver->number_or("low_stress_pressure_Pa", q.low_stress_pressure,
                                            NumberRange::left_open(0.0, 1.0e7));
  if (auto use = solver->optional_choice("low_stress_use", {"last_resort", "every_step"}))
    q.low_stress_use = *use == "every_step" ? mpm::quasi_static::StabilisationUse::every_step
                                            : mpm::quasi_static::StabilisationUse::last_resort;
  q.inside_body_weakness = solver->number_or("inside_body_weakness", q.inside_body_weakness,
                                             NumberRange::closed(0.0, 1.0));
  solver->check_no_unknown_keys();
}

double default_K0(const MaterialSpec& material) {
  return model_registry().at(material.model).at_rest_K0(*material.parameters);
}

MpmRegion read_region(TableReader& t, const MaterialCatalog& catalog, int index,
                      const std::vector<double>& x_nodes, const std::vector<double>& y_nodes) {
  MpmRegion r;
  r.source = fmt::format("{}:{}", t.file(), t.line());
  r.line = t.line();
  r.key = t.path();
  r.name = t.name_or("name", fmt::format("region{}", index + 1));
  t.declare({"x_min_m", "x_max_m", "y_min_m", "y_max_m", "particles_per_cell", "density_kg_per_m3",
             "material", "initial_stress", "K0", "e0", "e0_at", "igs", "igs_initial",
             "velocity_x_m_per_s", "velocity_y_m_per_s"});
  mpm::RectangleFill& f = r.fill;
  // Inside the grid.
  f.x_min = t.number("x_min_m", NumberRange::closed(x_nodes.front(), x_nodes.back()));
  f.x_max = t.number("x_max_m", NumberRange::left_open(f.x_min, x_nodes.back()));
  f.y_min = t.number("y_min_m", NumberRange::closed(y_nodes.front(), y_nodes.back()));
  f.y_max = t.number("y_max_m", NumberRange::left_open(f.y_min, y_nodes.back()));
  const std::vector<double> per_cell =
      t.number_array("particles_per_cell", NumberRange::closed(1, kMaxParticlesPerCell), 1, 2,
                     /*scalar_ok=*/true);
  for (double n : per_cell)
    if (n != std::floor(n))
      throw t.error("particles_per_cell",
                    fmt::format("not an integer: must be an integer in [1, {}] (per direction), "
                                "or [n_x, n_y]",
                                kMaxParticlesPerCell));
  f.particles_per_cell_x = static_cast<int>(per_cell.front());
  f.particles_per_cell_y = static_cast<int>(per_cell.back());
  f.density = t.number("density_kg_per_m3", NumberRange::positive());
  f.initial_velocity = {t.number_or("velocity_x_m_per_s", 0.0, kVelocityRange),
                        t.number_or("velocity_y_m_per_s", 0.0, kVelocityRange)};
  f.material = index;

  const std::string material_name = t.string("material");
  const MaterialSpec* material = catalog.find(material_name);
  if (material == nullptr)
    throw t.error("material",
                  fmt::format("unknown: must be a [[material]] name or a built-in set, one of {}",
                              fmt::join(catalog.names(), ", ")));
  r.material = *material;
  const bool hypoplastic = material->is_hypoplastic();
  if (hypoplastic) {
    r.igs_in_region = t.contains("igs");
    if (r.igs_in_region)
      r.igs = read_igs(t, "igs");
    else if (material->hypoplastic_material().igs)
      r.igs = material->hypoplastic_material().igs;
    else
      throw t.missing("igs", fmt::format("the hypoplastic model needs igs = one of {} or an "
                                         "inline table, in the region or its [[material]]",
                                         fmt::join(igs_choice_names(), ", ")));
    r.igs_compression =
        t.optional_choice("igs_initial", {"compression", "zero"}).value_or("compression") ==
        "compression";
  } else {
    for (const char* key : {"igs", "igs_initial"})
      if (t.contains(key))
        throw t.error(key, fmt::format("not allowed: the intergranular strain belongs to the "
                                       "hypoplastic model, and material \"{}\" is {}",
                                       material_name, material->model));
  }

  const std::string stress = t.choice("initial_stress", {"zero", "geostatic"});
  r.initial_stress = stress == "geostatic" ? MpmInitialStress::geostatic : MpmInitialStress::zero;
  if (r.initial_stress == MpmInitialStress::geostatic)
    r.K0 = t.number_or("K0", default_K0(*material), NumberRange::positive());
  else if (t.contains("K0"))
    throw t.error("K0", "not allowed: K0 applies to initial_stress = \"geostatic\" only");

  // The void ratio: required for the hypoplastic model, carried along by the others.
  if (hypoplastic && !t.contains("e0"))
    throw t.missing("e0",
                    "the initial void ratio e0 (> 0) is required for a hypoplastic "
                    "material");
  r.e0 = t.number_or("e0", 0.0, NumberRange::non_negative());
  if (hypoplastic && !t.contains("e0_at"))
    throw t.missing("e0_at",
                    "say which state e0 refers to: e0_at = \"initial-stress\" (e0 is the void "
                    "ratio at the initial stress) or \"zero-pressure\" (e0 is scaled from p = 0 "
                    "to the initial mean stress by Bauer's law)");
  if (auto at = t.optional_choice("e0_at", kConventions)) {
    r.e0_at = parse_void_ratio_convention(*at, "e0_at");
    if (!hypoplastic && r.e0_at == VoidRatioConvention::at_zero_pressure)
      throw t.error("e0_at", fmt::format("not allowed for material \"{}\" ({}): scaling from "
                                         "zero pressure needs the hypoplastic h_s and n; use "
                                         "\"initial-stress\"",
                                         material_name, material->model));
  }
  t.check_no_unknown_keys();
  return r;
}

// One side of [boundaries]: a condition by name or an absorbing boundary as a table.
void read_side(TableReader& sides, mpm::Side side, const char* name, MpmCase& c) {
  const toml::node* node = sides.node(name);
  if (node == nullptr) return;
  if (!node->is_table()) {
    c.boundaries[static_cast<std::size_t>(side)] =
        parse_boundary(sides.choice(name, kBoundaryNames));
    return;
  }
  TableReader t = *sides.table(name);
  t.choice("kind", {"absorbing"});
  mpm::AbsorbingBoundary b;
  b.side = side;
  b.density = t.number("density_kg_per_m3", NumberRange::positive());
  b.p_wave_speed = t.number("p_wave_speed_m_per_s", NumberRange::non_negative());
  b.s_wave_speed = t.number("s_wave_speed_m_per_s", NumberRange::non_negative());
  t.check_no_unknown_keys();
  c.boundaries[static_cast<std::size_t>(side)] = mpm::BoundaryCondition::free;
  c.solver.absorbing_boundaries.push_back(b);
}

// [[body]]: a pile (axisymmetry) or a convex polygon (plane strain).
MpmBody read_body(TableReader& t, mpm::Geometry geometry, int index) {
  MpmBody b;
  b.line = t.line();
  b.key = t.path();
  b.name = t.name_or("name", fmt::format("body{}", index + 1));
  t.declare({"kind", "radius_m", "tip_y_m", "tip", "apex_angle_deg", "vertices_m",
             "interface_friction_angle_deg", "contact_distance_m"});
  const bool axisymmetric = geometry == mpm::Geometry::axisymmetric;
  const std::string kind = t.choice("kind", {"pile", "polygon"});
  b.kind = kind == "pile" ? MpmBodyKind::pile : MpmBodyKind::polygon;
  if (b.kind == MpmBodyKind::pile && !axisymmetric)
    throw t.error("kind",
                  "not allowed in plane strain: a pile needs geometry kind = "
                  "\"axisymmetric\"; use \"polygon\"");
  if (b.kind == MpmBodyKind::polygon && axisymmetric)
    throw t.error("kind",
                  "not allowed in axisymmetry: a body there is a pile on the axis; use "
                  "\"pile\"");
  const auto forbid = [&](const char* key, const char* reason) {
    if (t.contains(key)) throw t.error(key, fmt::format("not allowed: {}", reason));
  };
  if (b.kind == MpmBodyKind::pile) {
    forbid("vertices_m", "a pile is given by radius_m, tip_y_m and tip");
    b.radius = t.number("radius_m", NumberRange::positive());
    b.tip_y = t.number("tip_y_m", NumberRange::any());
    const std::string tip = t.choice("tip", {"conical", "flat"});
    if (tip == "flat") {
      forbid("apex_angle_deg", "a flat tip has no apex angle");
      b.apex_angle = kPi;
    } else {
      b.apex_angle =
          t.number_or("apex_angle_deg", 60.0, NumberRange::open(0.0, 180.0)) * kPi / 180.0;
    }
  } else {
    for (const char* key : {"radius_m", "tip_y_m", "tip", "apex_angle_deg"})
      forbid(key, "a polygon is given by vertices_m");
    const toml::node* node = t.node("vertices_m");
    if (node == nullptr)
      throw t.missing("vertices_m",
                      "the polygon's corners, vertices_m = [[x, y], ...] [m], at "
                      "least three, convex");
    const char* allowed = "an array of at least three [x, y] pairs of finite numbers [m]";
    const toml::array* list = node->as_array();
    if (list == nullptr || list->size() < 3) throw t.error("vertices_m", allowed);
    for (const toml::node& vertex : *list) {
      const toml::array* pair = vertex.as_array();
      if (pair == nullptr || pair->size() != 2) throw t.error("vertices_m", allowed);
      mpm::Vec2 v;
      for (std::size_t k = 0; k < 2; ++k) {
        const std::optional<double> x = (*pair)[k].value<double>();
        if (!x || !std::isfinite(*x)) throw t.error("vertices_m", allowed);
        v[static_cast<Eigen::Index>(k)] = *x;
      }
      b.vertices.push_back(v);
    }
  }
  b.friction =
      std::tan(t.number("interface_friction_angle_deg", {0.0, 90.0, false, true}) * kPi / 180.0);
  b.contact_distance = t.number_or("contact_distance_m", 0.0, NumberRange::positive());
  t.check_no_unknown_keys();
  try {
    make_rigid_body(b);
  } catch (const InvalidValue& e) {
    throw t.error(
        b.kind == MpmBodyKind::pile ? "radius_m" : "vertices_m",
        fmt::format("not a valid body: {} = {} must be {}", e.key(), e.value(), e.allowed()));
  }
  return b;
}

// [[traction]]: a uniform traction on one side of a region.
MpmTraction read_traction(TableReader& t, const std::vector<MpmRegion>& regions) {
  MpmTraction tr;
  tr.line = t.line();
  tr.key = t.path();
  const std::string region = t.string("region");
  std::vector<std::string> names;
  int found = -1, matches = 0;
  for (std::size_t i = 0; i < regions.size(); ++i) {
    names.push_back(regions[i].name);
    if (regions[i].name == region) found = static_cast<int>(i), ++matches;
  }
  if (matches == 0)
    throw t.error("region", fmt::format("unknown: must be the name of a [[region]], one of {}",
                                        quoted_names(names)));
  if (matches > 1)
    throw t.error("region",
                  "ambiguous: several regions have this name; give them distinct "
                  "names");
  tr.region = found;
  const std::string side = t.choice("side", {"left", "right", "bottom", "top"});
  tr.side = side == "left"     ? mpm::Side::left
            : side == "right"  ? mpm::Side::right
            : side == "bottom" ? mpm::Side::bottom
                               : mpm::Side::top;
  tr.normal = t.number("normal_kPa", NumberRange::any()) * kKPa;
  tr.shear = t.number_or("shear_kPa", 0.0, NumberRange::any()) * kKPa;
  t.check_no_unknown_keys();
  return tr;
}

}  // namespace

namespace mpm_case_detail {

// Names as a list for messages: "a", "b".
std::string quoted_names(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) {
    if (!text.empty()) text += ", ";
    text += '"';
    text += name;
    text += '"';
  }
  return text.empty() ? std::string("(none)") : text;
}

}  // namespace mpm_case_detail

MpmCase read_mpm_case_text(std::string_view text, const std::string& source_name) {
  const toml::table document = parse_toml_text(text, source_name);
  TableReader root(document, source_name, "");
  MpmCase c;
  c.source = source_name;
  c.title = root.optional_string("title").value_or("");

  std::optional<TableReader> geometry = root.table("geometry");
  if (!geometry)
    throw root.missing("geometry", "[geometry] with kind = \"plane-strain\" or \"axisymmetric\"");
  c.geometry = geometry->choice("kind", {"plane-strain", "axisymmetric"}) == "axisymmetric"
                   ? mpm::Geometry::axisymmetric
                   : mpm::Geometry::plane_strain;
  geometry->check_no_unknown_keys();

  std::optional<TableReader> grid = root.table("grid");
  if (!grid) throw root.missing("grid", "[grid] with [grid.x] and [grid.y]");
  c.x_axis = read_axis(*grid, "x", c.x_nodes);
  c.y_axis = read_axis(*grid, "y", c.y_nodes);
  grid->check_no_unknown_keys();
  if (c.geometry == mpm::Geometry::axisymmetric && c.x_nodes.front() != 0.0)
    throw InputError(source_name, grid->line(), "grid.x.min_m", fmt::format("{}", c.x_nodes[0]),
                     "must be 0 in axisymmetry: the left side of the grid is the axis r = 0");

  c.boundaries.fill(mpm::BoundaryCondition::free);
  read_solver(root.table("solver"), c);
  c.solver.geometry = c.geometry;
  if (std::optional<TableReader> sides = root.table("boundaries")) {
    const char* names[4] = {"left", "right", "bottom", "top"};  // the order of mpm::Side
    const mpm::Side order[4] = {mpm::Side::left, mpm::Side::right, mpm::Side::bottom,
                                mpm::Side::top};
    for (int s = 0; s < 4; ++s) read_side(*sides, order[s], names[s], c);
    sides->check_no_unknown_keys();
  }

  MaterialCatalog catalog;
  catalog.read(root, default_integrator(c.analysis));
  c.integrator = catalog.integrator();
  c.materials = catalog.materials();

  std::vector<TableReader> regions = root.tables("region");
  std::vector<TableReader> bodies = root.tables("body");
  std::vector<TableReader> tractions = root.tables("traction");
  std::vector<TableReader> phases = root.tables("phase");
  root.check_no_unknown_keys();
  if (regions.empty())
    throw InputError(source_name, 0, "region", "",
                     "missing: a case needs at least one [[region]] of particles");
  if (phases.empty())
    throw InputError(source_name, 0, "phase", "", "missing: a case needs at least one [[phase]]");

  for (std::size_t i = 0; i < regions.size(); ++i) {
    MpmRegion r = read_region(regions[i], catalog, static_cast<int>(i), c.x_nodes, c.y_nodes);
    try {
      c.models.push_back(make_model(r.material, r.igs, catalog.integrator()));
    } catch (const InvalidValue& e) {
      throw regions[i].error_from(e);
    }
    c.material_names.push_back(r.material.name);
    c.regions.push_back(std::move(r));
  }
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    MpmBody b = read_body(bodies[i], c.geometry, static_cast<int>(i));
    for (const MpmBody& other : c.bodies)
      if (other.name == b.name)
        throw bodies[i].error("name", "already used: bodies need distinct names");
    c.bodies.push_back(std::move(b));
  }
  for (TableReader& t : tractions) c.tractions.push_back(read_traction(t, c.regions));
  for (std::size_t i = 0; i < phases.size(); ++i)
    c.phases.push_back(read_phase(phases[i], c, catalog, static_cast<int>(i)));
  try {
    c.solver.validate();
  } catch (const InvalidValue& e) {
    throw InputError(source_name, 0, "solver." + e.key(), e.value(), e.what());
  }
  return c;
}

MpmCase read_mpm_case(const std::filesystem::path& path) {
  return read_mpm_case_text(read_case_text(path), path.string());
}

}  // namespace pilempm
