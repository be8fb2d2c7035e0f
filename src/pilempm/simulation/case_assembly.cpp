// The assembly of a run from a typed case: see case_assembly.hpp.
#include "pilempm/simulation/case_assembly.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/constitutive/hypoplastic/hypoplastic_parameters.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/core/tensor.hpp"

namespace pilempm::simulation {

namespace {

constexpr double kKPa = 1.0e3;

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

mpm::Grid make_mpm_grid(const MpmCase& c) {
  mpm::Grid grid(mpm::GridAxis(c.x_nodes), mpm::GridAxis(c.y_nodes));
  const mpm::Side sides[4] = {mpm::Side::left, mpm::Side::right, mpm::Side::bottom, mpm::Side::top};
  for (std::size_t s = 0; s < 4; ++s) grid.set_boundary(sides[s], c.boundaries[s]);
  if (c.geometry == mpm::Geometry::axisymmetric) grid.set_axis_of_symmetry(true);
  return grid;
}

namespace {

// The geostatic state of one particle of region `r` at `position` under `gravity` = N g.
void geostatic_state(const MpmCase& c, const MpmRegion& r, const ConstitutiveModel& model,
                     const mpm::Vec2& position, double gravity, MaterialState& state) {
  const auto* hypoplastic = dynamic_cast<const Hypoplastic*>(&model);
  double mean = 0.0;
  if (r.initial_stress == MpmInitialStress::geostatic) {
    const double vertical = overburden(c, position.x(), position.y(), gravity);
    state.stress = Vec6::Zero();
    state.stress[k11] = -r.K0 * vertical;
    state.stress[k22] = -vertical;
    state.stress[k33] = -r.K0 * vertical;
    mean = vertical * (1.0 + 2.0 * r.K0) / 3.0;
  }
  state.void_ratio = r.e0;
  if (hypoplastic != nullptr) {
    state.void_ratio = initial_void_ratio(hypoplastic->parameters(), r.e0, r.e0_at, mean);
    Hypoplastic::intergranular_strain(state) = Vec6::Zero();
    if (hypoplastic->intergranular().enabled() && r.igs_compression)
      Hypoplastic::intergranular_strain(state) =
          -hypoplastic->intergranular().R / kSqrt3 * identity6();
  }
  if (hypoplastic != nullptr && (!std::isfinite(state.void_ratio) || state.void_ratio <= 0.0))
    throw InputError(c.source, r.line, r.key + ".e0", fmt::format("{}", r.e0),
                     fmt::format("gives the void ratio {} at p = {} kPa: must be > 0",
                                 state.void_ratio, mean / kKPa));
}

}  // namespace

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
    if (particles.size() == first)
      throw InputError(c.source, r.line, r.key, "",
                       fmt::format("region \"{}\" holds no particle: its rectangle covers no "
                                   "particle position of the grid's cells (make it larger or the "
                                   "grid finer)",
                                   r.name));
    const ConstitutiveModel& model = *c.models[static_cast<std::size_t>(r.fill.material)];
    for (std::size_t p = first; p < particles.size(); ++p)
      geostatic_state(c, r, model, particles.position[p], gravity, particles.state[p]);
  }
  if (c.bodies.empty()) return particles;
  // A body stands where it is put (a pile wished in place): no particle starts inside it.
  std::vector<mpm::RigidBody> bodies;
  for (const MpmBody& b : c.bodies) bodies.push_back(make_rigid_body(b));
  return mpm::particles_outside(particles, bodies);
}

void set_geostatic_state(const MpmCase& c, mpm::MpmState& state, double gravity) {
  mpm::Particles& particles = state.particles();
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const auto region = static_cast<std::size_t>(particles.material[p]);  // one model a region
    const MpmRegion& r = c.regions.at(region);
    if (r.initial_stress != MpmInitialStress::geostatic) continue;
    geostatic_state(c, r, *state.materials()[region], particles.position[p], gravity,
                    particles.state[p]);
    particles.velocity[p] = mpm::Vec2::Zero();
  }
}

std::string_view to_string(MpmPhaseRole role) {
  switch (role) {
    case MpmPhaseRole::none:
      return "";
    case MpmPhaseRole::initial_stress:
      return "initial-stress";
    case MpmPhaseRole::installation:
      return "installation";
    case MpmPhaseRole::relaxation:
      return "relaxation";
    case MpmPhaseRole::load_test:
      return "load-test";
  }
  return "";
}

mpm::RigidBody make_rigid_body(const MpmBody& b) {
  mpm::RigidBody body = b.kind == MpmBodyKind::pile
                            ? mpm::RigidBody::pile(b.radius, b.tip_y, b.apex_angle)
                            : mpm::RigidBody::polygon(b.vertices);
  body.set_friction(b.friction);
  body.set_contact_distance(b.contact_distance);
  return body;
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
  mpm::Solver solver(std::move(grid), std::move(particles), c.models, settings);
  for (const MpmBody& b : c.bodies) solver.add_rigid_body(make_rigid_body(b));
  return solver;
}

mpm::quasi_static::Settings quasi_static_settings(const MpmCase& c) {
  mpm::quasi_static::Settings s = c.quasi_static;
  s.geometry = c.geometry;
  s.shape_function = c.solver.shape_function;
  s.gravity = c.solver.gravity;
  s.threads = c.solver.threads;
  s.volumetric_averaging = c.solver.volumetric_smoothing;
  // A diagnostic, not a setting of the case: a line per Newton iteration on stderr.
  const char* trace = std::getenv("PILEMPM_NEWTON_TRACE");
  if (trace != nullptr && *trace != '\0' && std::string_view(trace) != "0") s.trace = stderr;
  s.trace_tangent = s.trace != nullptr && std::string_view(trace) == "tangent";
  return s;
}

mpm::quasi_static::QuasiStaticSolver make_quasi_static_solver(const MpmCase& c) {
  for (const MpmRegion& r : c.regions)
    if (r.fill.initial_velocity != mpm::Vec2::Zero())
      throw InputError(c.source, r.line, r.key + ".velocity_x_m_per_s", "",
                       "an initial velocity needs inertia: the quasi-static analysis has none "
                       "(use [solver] analysis = \"explicit\")");
  if (!c.solver.absorbing_boundaries.empty())
    throw InputError(c.source, 0, "boundaries", "absorbing",
                     "absorbing boundaries damp waves, which the quasi-static analysis does not "
                     "have (use [solver] analysis = \"explicit\", or a fixed or roller side)");
  mpm::Grid grid = make_mpm_grid(c);
  mpm::Particles particles = make_mpm_particles(c, grid);
  mpm::quasi_static::QuasiStaticSolver solver(std::move(grid), std::move(particles), c.models,
                                              quasi_static_settings(c));
  for (const MpmBody& b : c.bodies) solver.add_rigid_body(make_rigid_body(b));
  return solver;
}

std::string_view to_string(MpmAnalysis analysis) {
  return analysis == MpmAnalysis::quasi_static ? "quasi-static" : "explicit";
}

IntegratorSettings default_integrator(MpmAnalysis analysis) {
  IntegratorSettings settings;
  if (analysis == MpmAnalysis::quasi_static)
    settings.scheme = IntegratorSettings::Scheme::bogacki_shampine;
  return settings;
}

}  // namespace pilempm::simulation
