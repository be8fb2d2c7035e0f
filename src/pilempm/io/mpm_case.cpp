// MPM case files: see mpm_case.hpp and docs/mpm-case-files.md.
#include "pilempm/io/mpm_case.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <utility>

#include "pilempm/constitutive/hypoplastic.hpp"
#include "pilempm/core/tensor.hpp"

namespace pilempm {

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

// One axis of [grid]: [grid.x] or [grid.y].
std::vector<double> read_axis(TableReader& grid, std::string_view key) {
  std::optional<TableReader> axis = grid.table(key);
  if (!axis)
    throw grid.missing(key, fmt::format("the {} axis: a table with spacing = \"uniform\" or "
                                        "\"graded\", min_m, max_m and its cells",
                                        key));
  const std::string spacing = axis->choice("spacing", {"uniform", "graded"});
  axis->declare({"min_m", "max_m", "cells", "band_min_m", "band_max_m", "fine_spacing_m",
                 "growth_ratio", "max_spacing_m"});
  const double start = axis->number("min_m", NumberRange::any());
  const double end = axis->number("max_m", NumberRange::above(start));
  try {
    if (spacing == "uniform") {
      const int cells = axis->integer("cells", 1, kMaxCells);
      axis->check_no_unknown_keys();
      return mpm::GridAxis::uniform(start, end, cells).nodes();
    }
    const double band_start = axis->number("band_min_m", NumberRange::closed(start, end));
    const double band_end = axis->number("band_max_m", NumberRange::left_open(band_start, end));
    const double fine = axis->number("fine_spacing_m", NumberRange::positive());
    const double growth = axis->number("growth_ratio", NumberRange::closed(1.0, 10.0));
    const double max_spacing =
        axis->number_or("max_spacing_m", NumberRange::kInf, NumberRange::at_least(fine));
    axis->check_no_unknown_keys();
    if ((end - start) / fine > kMaxCells)
      throw axis->error("fine_spacing_m", fmt::format("too small: more than {} cells", kMaxCells));
    return mpm::GridAxis::graded(start, end, band_start, band_end, fine, growth, max_spacing)
        .nodes();
  } catch (const InvalidValue& e) {
    throw axis->error_from(e);
  }
}

mpm::SolverSettings read_solver(std::optional<TableReader> solver) {
  mpm::SolverSettings s;
  if (!solver) return s;
  if (auto scheme = solver->optional_choice("scheme", {"musl", "usl"}))
    s.scheme = *scheme == "usl" ? mpm::UpdateScheme::usl : mpm::UpdateScheme::musl;
  if (auto shape = solver->optional_choice("shape_function", {"linear", "ugimp", "cpgimp"}))
    s.shape_function = *shape == "linear"  ? mpm::ShapeFunction::linear
                       : *shape == "ugimp" ? mpm::ShapeFunction::ugimp
                                           : mpm::ShapeFunction::cpgimp;
  s.flip_fraction = solver->number_or("flip_fraction", s.flip_fraction, NumberRange::closed(0, 1));
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
  solver->check_no_unknown_keys();
  return s;
}

double default_K0(const MaterialSpec& material) {
  switch (material.kind) {
    case ModelKind::hypoplastic:
      return 1.0 - std::sin(material.hypoplastic.phi_c_deg * kPi / 180.0);  // Jáky
    case ModelKind::mohr_coulomb:
      return 1.0 - std::sin(material.mohr_coulomb.friction_angle_deg * kPi / 180.0);
    case ModelKind::linear_elastic:
      break;
  }
  const double nu = material.elastic.poisson_ratio;  // oedometric ν / (1 - ν)
  return nu / (1.0 - nu);
}

MpmRegion read_region(TableReader& t, const MaterialCatalog& catalog, int index,
                      const std::vector<double>& x_nodes, const std::vector<double>& y_nodes) {
  MpmRegion r;
  r.source = fmt::format("{}:{}", t.file(), t.line());
  r.line = t.line();
  r.key = t.path();
  r.name = t.optional_string("name").value_or(fmt::format("region{}", index + 1));
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
  f.initial_velocity = {t.number_or("velocity_x_m_per_s", 0.0, NumberRange::any()),
                        t.number_or("velocity_y_m_per_s", 0.0, NumberRange::any())};
  f.material = index;

  const std::string material_name = t.string("material");
  const MaterialSpec* material = catalog.find(material_name);
  if (material == nullptr)
    throw t.error("material",
                  fmt::format("unknown: must be a [[material]] name or a built-in set, one of {}",
                              fmt::join(catalog.names(), ", ")));
  r.material = *material;
  const bool hypoplastic = material->kind == ModelKind::hypoplastic;
  if (hypoplastic) {
    if (t.contains("igs"))
      r.igs = read_igs(t, "igs");
    else if (material->igs)
      r.igs = material->igs;
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
                                       material_name, to_string(material->kind)));
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
                                         material_name, to_string(material->kind)));
  }
  t.check_no_unknown_keys();
  return r;
}

MpmPhase read_phase(TableReader& t, const mpm::SolverSettings& solver, int index) {
  MpmPhase p;
  p.name = t.optional_string("name").value_or(fmt::format("phase{}", index + 1));
  p.duration = t.number("duration_s", NumberRange::positive());
  p.gravity_multiplier =
      t.number_or("gravity_multiplier", solver.gravity_multiplier, NumberRange::non_negative());
  p.local_damping = t.number_or("local_damping", solver.local_damping, {0.0, 1.0, false, true});
  p.output_interval =
      t.number_or("output_interval_s", p.duration, NumberRange::left_open(0.0, p.duration));
  p.energy_interval = t.number_or("energy_interval_s", p.output_interval / 10.0,
                                  NumberRange::left_open(0.0, p.duration));
  t.check_no_unknown_keys();
  return p;
}

// σ_v at (x, y) from the regions above it (horizontally layered ground) under N g [Pa].
double overburden(const MpmCase& c, double x, double y, double gravity) {
  double stress = 0.0;
  for (const MpmRegion& r : c.regions) {
    const mpm::RectangleFill& f = r.fill;
    if (x < f.x_min || x >= f.x_max) continue;
    stress += f.density * gravity * std::max(0.0, f.y_max - std::max(y, f.y_min));
  }
  return stress;
}

}  // namespace

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
  c.x_nodes = read_axis(*grid, "x");
  c.y_nodes = read_axis(*grid, "y");
  grid->check_no_unknown_keys();
  if (c.geometry == mpm::Geometry::axisymmetric && c.x_nodes.front() != 0.0)
    throw InputError(source_name, grid->line(), "grid.x.min_m", fmt::format("{}", c.x_nodes[0]),
                     "must be 0 in axisymmetry: the left side of the grid is the axis r = 0");

  c.boundaries.fill(mpm::BoundaryCondition::free);
  if (std::optional<TableReader> sides = root.table("boundaries")) {
    const char* names[4] = {"left", "right", "bottom", "top"};  // the order of mpm::Side
    for (int s = 0; s < 4; ++s)
      if (auto value = sides->optional_choice(names[s], kBoundaryNames))
        c.boundaries[static_cast<std::size_t>(s)] = parse_boundary(*value);
    sides->check_no_unknown_keys();
  }

  c.solver = read_solver(root.table("solver"));
  c.solver.geometry = c.geometry;

  MaterialCatalog catalog;
  catalog.read(root);

  std::vector<TableReader> regions = root.tables("region");
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
  for (std::size_t i = 0; i < phases.size(); ++i)
    c.phases.push_back(read_phase(phases[i], c.solver, static_cast<int>(i)));
  try {
    c.solver.validate();
  } catch (const InvalidValue& e) {
    throw InputError(source_name, 0, "solver." + e.key(), e.value(), e.what());
  }
  return c;
}

MpmCase read_mpm_case(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(name, 0, "", "", "cannot open the case file for reading");
  std::ostringstream text;
  text << in.rdbuf();
  return read_mpm_case_text(text.str(), name);
}

mpm::Grid make_mpm_grid(const MpmCase& c) {
  mpm::Grid grid(mpm::GridAxis(c.x_nodes), mpm::GridAxis(c.y_nodes));
  const mpm::Side sides[4] = {mpm::Side::left, mpm::Side::right, mpm::Side::bottom, mpm::Side::top};
  for (std::size_t s = 0; s < 4; ++s) grid.set_boundary(sides[s], c.boundaries[s]);
  if (c.geometry == mpm::Geometry::axisymmetric) grid.set_axis_of_symmetry(true);
  return grid;
}

mpm::Particles make_mpm_particles(const MpmCase& c, const mpm::Grid& grid) {
  mpm::Particles particles;
  const double gravity =
      c.solver.gravity *
      (c.phases.empty() ? c.solver.gravity_multiplier : c.phases.front().gravity_multiplier);
  for (const MpmRegion& r : c.regions) {
    const std::size_t first = particles.size();
    try {
      mpm::fill_rectangle(particles, grid, c.geometry, r.fill);
    } catch (const InvalidValue& e) {
      throw InputError(c.source, r.line, r.key + "." + e.key(), e.value(), e.what());
    }
    const auto* hypoplastic = dynamic_cast<const Hypoplastic*>(c.models[r.fill.material].get());
    for (std::size_t p = first; p < particles.size(); ++p) {
      MaterialState& state = particles.state[p];
      double mean = 0.0;
      if (r.initial_stress == MpmInitialStress::geostatic) {
        const double vertical =
            overburden(c, particles.position[p].x(), particles.position[p].y(), gravity);
        state.stress = Vec6::Zero();
        state.stress[k11] = -r.K0 * vertical;
        state.stress[k22] = -vertical;
        state.stress[k33] = -r.K0 * vertical;
        mean = vertical * (1.0 + 2.0 * r.K0) / 3.0;
      }
      state.void_ratio = r.e0;
      if (hypoplastic != nullptr) {
        state.void_ratio = initial_void_ratio(hypoplastic->parameters(), r.e0, r.e0_at, mean);
        if (hypoplastic->intergranular().enabled() && r.igs_compression)
          state.intergranular_strain = -hypoplastic->intergranular().R / kSqrt3 * identity6();
      }
      if (!std::isfinite(state.void_ratio) || state.void_ratio <= 0.0)
        throw InputError(c.source, r.line, r.key + ".e0", fmt::format("{}", r.e0),
                         fmt::format("gives the void ratio {} at p = {} kPa: must be > 0",
                                     state.void_ratio, mean / kKPa));
    }
  }
  return particles;
}

mpm::SolverSettings phase_settings(const MpmCase& c, const MpmPhase& phase) {
  mpm::SolverSettings s = c.solver;
  s.gravity_multiplier = phase.gravity_multiplier;
  s.local_damping = phase.local_damping;
  return s;
}

mpm::Solver make_mpm_solver(const MpmCase& c) {
  mpm::Grid grid = make_mpm_grid(c);
  mpm::Particles particles = make_mpm_particles(c, grid);
  const mpm::SolverSettings settings =
      c.phases.empty() ? c.solver : phase_settings(c, c.phases.front());
  return mpm::Solver(std::move(grid), std::move(particles), c.models, settings);
}

}  // namespace pilempm
