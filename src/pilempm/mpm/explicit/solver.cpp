#include "pilempm/mpm/explicit/solver.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>

#include "pilempm/core/error.hpp"
#include "pilempm/mpm/explicit/grid_to_particles.hpp"
#include "pilempm/mpm/explicit/grid_update.hpp"
#include "pilempm/mpm/explicit/musl_remap.hpp"
#include "pilempm/mpm/explicit/particles_to_grid.hpp"
#include "pilempm/mpm/thread_count.hpp"

namespace pilempm::mpm {

namespace {

// The run-state arrays of contact = surface.
constexpr const char* kSurfaceForces = "surface_contact_tangential_force_N";
constexpr const char* kSurfaceBodies = "surface_contact_body";
constexpr const char* kSurfacePositions = "surface_contact_relative_position_m";
constexpr const char* kSurfaceFrequency = "surface_contact_frequency_squared_per_s2";
constexpr const char* kSurfaceModulus = "surface_contact_modulus_Pa";  // per material

}  // namespace

void SolverSettings::validate() const {
  if (!(flip_fraction >= 0.0 && flip_fraction <= 1.0))
    throw InvalidValue("flip_fraction", format_value(flip_fraction), "in [0, 1]");
  if (xpic_order < 1 || xpic_order > 8)
    throw InvalidValue("xpic_order", std::to_string(xpic_order), "in [1, 8] (1: PIC)");
  if (!(gravity >= 0.0 && std::isfinite(gravity)))
    throw InvalidValue("gravity_m_per_s2", format_value(gravity), ">= 0 (acts along -y)");
  if (!(gravity_multiplier >= 0.0 && std::isfinite(gravity_multiplier)))
    throw InvalidValue("gravity_multiplier", format_value(gravity_multiplier), ">= 0");
  if (!(local_damping >= 0.0 && local_damping < 1.0))
    throw InvalidValue("local_damping", format_value(local_damping), "in [0, 1)");
  if (!(mass_scaling >= 1.0 && std::isfinite(mass_scaling)))
    throw InvalidValue("mass_scaling", format_value(mass_scaling), ">= 1");
  if (!(courant_number > 0.0 && courant_number <= 1.0))
    throw InvalidValue("courant_number", format_value(courant_number), "in (0, 1]");
  if (!(fixed_time_step >= 0.0 && std::isfinite(fixed_time_step)))
    throw InvalidValue("fixed_time_step_s", format_value(fixed_time_step), ">= 0 (0: CFL step)");
  if (wave_speed_interval < 1)
    throw InvalidValue("wave_speed_interval", std::to_string(wave_speed_interval), ">= 1");
  if (contact == ContactScheme::surface) surface_contact.validate();
  if (threads < 0) throw InvalidValue("threads", std::to_string(threads), ">= 0 (0: default)");
  bool side_taken[4] = {false, false, false, false};
  for (const AbsorbingBoundary& boundary : absorbing_boundaries) {
    const int side = static_cast<int>(boundary.side);
    if (side < 0 || side > 3)
      throw InvalidValue("absorbing boundary side", std::to_string(side), "0..3");
    if (side_taken[side])
      throw InvalidValue("absorbing boundary side", std::to_string(side), "at most one per side");
    side_taken[side] = true;
    if (!(boundary.density > 0.0 && std::isfinite(boundary.density)))
      throw InvalidValue("absorbing boundary density_kg_per_m3", format_value(boundary.density),
                         "> 0");
    if (!(boundary.p_wave_speed >= 0.0 && std::isfinite(boundary.p_wave_speed)))
      throw InvalidValue("absorbing boundary p_wave_speed_m_per_s",
                         format_value(boundary.p_wave_speed), ">= 0");
    if (!(boundary.s_wave_speed >= 0.0 && std::isfinite(boundary.s_wave_speed)))
      throw InvalidValue("absorbing boundary s_wave_speed_m_per_s",
                         format_value(boundary.s_wave_speed), ">= 0");
  }
}

Solver::Solver(Grid grid, Particles particles, std::vector<ModelPtr> materials,
               SolverSettings settings)
    : grid_(std::move(grid)),
      particles_(std::move(particles)),
      materials_(std::move(materials)),
      settings_(settings) {
  settings_.validate();
  if (materials_.empty()) throw InvalidValue("materials", "none", "at least one model");
  for (std::size_t m = 0; m < materials_.size(); ++m)
    if (!materials_[m]) throw InvalidValue(fmt::format("material {}", m), "null", "a model");
  for (const ModelPtr& model : materials_) models_.push_back(model.get());
  if (settings_.geometry == Geometry::axisymmetric && grid_.x_axis().start() < 0.0)
    throw InvalidValue("grid x start (radius)", format_value(grid_.x_axis().start()),
                       ">= 0 in axisymmetry");
  check_particles();

  if (settings_.geometry == Geometry::axisymmetric && grid_.x_axis().start() == 0.0)
    grid_.set_axis_of_symmetry(true);

  const std::size_t count = particles_.size();
  threads_ = settings_.threads > 0 ? settings_.threads : default_thread_count(count);
  stencils_.resize(count);
  start_radius_.resize(count);
  scatter_.resize(threads_, grid_.node_count());
  grid_update_tallies_.resize(static_cast<std::size_t>(threads_));
  particle_motion_tallies_.resize(static_cast<std::size_t>(threads_));
  stress_update_tallies_.resize(static_cast<std::size_t>(threads_));
  node_motion_.assign(static_cast<std::size_t>(grid_.node_count()), NodeMotion{});

  update_dashpots();
  for (std::size_t p = 0; p < count; ++p) {
    const double speed = particles_.velocity[p].norm();
    energies_.kinetic += 0.5 * settings_.mass_scaling * particles_.mass[p] * speed * speed;
    max_particle_speed_ = std::max(max_particle_speed_, speed);
  }
}

void Solver::check_particles() const {
  const Particles& p = particles_;
  const std::size_t n = p.size();
  for (std::size_t size :
       {p.velocity.size(), p.mass.size(), p.initial_volume.size(), p.volume.size(),
        p.initial_half_size.size(), p.half_size.size(), p.deformation_gradient.size(),
        p.out_of_plane_stretch.size(), p.material.size(), p.state.size(), p.external_force.size()})
    if (size != n)
      throw InvalidValue("particle field length", std::to_string(size),
                         fmt::format("{} (the number of positions)", n));
  for (std::size_t i = 0; i < n; ++i) {
    auto what = [i](const char* field) { return fmt::format("particle {} {}", i, field); };
    if (p.material[i] < 0 || p.material[i] >= static_cast<int>(materials_.size()))
      throw InvalidValue(what("material"), std::to_string(p.material[i]),
                         fmt::format("in [0, {}]", materials_.size() - 1));
    if (!(p.mass[i] > 0.0 && std::isfinite(p.mass[i])))
      throw InvalidValue(what("mass"), format_value(p.mass[i]), "> 0");
    if (!(p.volume[i] > 0.0 && std::isfinite(p.volume[i])))
      throw InvalidValue(what("volume"), format_value(p.volume[i]), "> 0");
    const Vec2& x = p.position[i];
    if (!(x.allFinite() && grid_.contains(x.x(), x.y())))
      throw InvalidValue(what("position"),
                         fmt::format("({}, {})", format_value(x.x()), format_value(x.y())),
                         "inside the grid");
    if (settings_.geometry == Geometry::axisymmetric && !(x.x() > 0.0))
      throw InvalidValue(what("radius"), format_value(x.x()), "> 0 in axisymmetry");
  }
}

void Solver::set_settings(const SolverSettings& settings) {
  settings.validate();
  if (settings.geometry != settings_.geometry)
    throw InvalidValue("geometry", "changed", "the same for the whole run");
  if (settings.threads != settings_.threads)
    throw InvalidValue("threads", std::to_string(settings.threads),
                       fmt::format("{} (fixed when the solver is made)", settings_.threads));
  settings_ = settings;
  wave_speed_step_ = -1;
  update_dashpots();
}

void Solver::set_material(int index, ModelPtr model) {
  if (index < 0 || index >= static_cast<int>(materials_.size()))
    throw InvalidValue("material index", std::to_string(index),
                       fmt::format("in [0, {}]", materials_.size() - 1));
  if (!model) throw InvalidValue(fmt::format("material {}", index), "null", "a model");
  models_[index] = model.get();
  materials_[index] = std::move(model);
  wave_speed_step_ = -1;
}

double Solver::vertical_momentum() const {
  double momentum = 0.0;
  for (std::size_t p = 0; p < particles_.size(); ++p)
    momentum += particles_.mass[p] * particles_.velocity[p].y();
  return momentum * settings_.mass_scaling;
}

SolverRunState Solver::run_state() const {
  SolverRunState state;
  state.time = time_;
  state.steps = steps_;
  state.energies = energies_;
  state.max_wave_speed = max_wave_speed_;
  state.wave_speed_step = wave_speed_step_;
  state.max_particle_speed = max_particle_speed_;
  state.rigid_body_forces = rigid_body_forces_;
  if (!corner_contacts_.empty()) {
    // contact = surface: the corners' friction histories and the springs' frequency bound.
    std::vector<double> force, body, relative;
    for (const CornerContact& c : corner_contacts_) {
      force.insert(force.end(), {c.history.tangential_force.x(), c.history.tangential_force.y()});
      body.push_back(c.history.body);
      relative.insert(relative.end(), {c.relative_position.x(), c.relative_position.y()});
    }
    state.scheme_arrays = {{kSurfaceForces, std::move(force)},
                           {kSurfaceBodies, std::move(body)},
                           {kSurfacePositions, std::move(relative)},
                           {kSurfaceFrequency, {surface_frequency_squared_}},
                           {kSurfaceModulus, surface_contact_modulus_}};
  }
  return state;
}

void Solver::restore_run_state(const SolverRunState& state) {
  if (state.rigid_body_forces.size() != rigid_bodies_.size())
    throw InvalidValue("rigid body forces in the run state",
                       std::to_string(state.rigid_body_forces.size()),
                       fmt::format("{} (one per rigid body)", rigid_bodies_.size()));
  for (std::size_t b = 0; b < rigid_bodies_.size(); ++b)
    if (state.rigid_body_forces[b].parts.size() !=
        static_cast<std::size_t>(rigid_bodies_[b].part_count()))
      throw InvalidValue(fmt::format("surface parts of rigid body {} in the run state", b),
                         std::to_string(state.rigid_body_forces[b].parts.size()),
                         std::to_string(rigid_bodies_[b].part_count()));
  time_ = state.time;
  steps_ = state.steps;
  energies_ = state.energies;
  max_wave_speed_ = state.max_wave_speed;
  wave_speed_step_ = state.wave_speed_step;
  max_particle_speed_ = state.max_particle_speed;
  rigid_body_forces_ = state.rigid_body_forces;
  corner_contacts_.clear();
  surface_frequency_squared_ = 0.0;
  surface_contact_modulus_.clear();
  const std::size_t corners = 4 * particles_.size();
  auto array = [&](const char* name, std::size_t size) -> const std::vector<double>* {
    for (const auto& [key, values] : state.scheme_arrays)
      if (key == name) {
        if (values.size() != size)
          throw InvalidValue(fmt::format("run state array {}", name), std::to_string(values.size()),
                             std::to_string(size));
        return &values;
      }
    return nullptr;
  };
  const std::vector<double>* force = array(kSurfaceForces, 2 * corners);
  const std::vector<double>* body = array(kSurfaceBodies, corners);
  const std::vector<double>* relative = array(kSurfacePositions, 2 * corners);
  const std::vector<double>* frequency = array(kSurfaceFrequency, 1);
  if (force && body && relative && frequency) {
    corner_contacts_.resize(corners);
    for (std::size_t c = 0; c < corners; ++c) {
      CornerContact& contact = corner_contacts_[c];
      contact.history.tangential_force = Vec2((*force)[2 * c], (*force)[2 * c + 1]);
      contact.history.body = static_cast<int>((*body)[c]);
      contact.relative_position = Vec2((*relative)[2 * c], (*relative)[2 * c + 1]);
    }
    surface_frequency_squared_ = frequency->front();
  }
  // A checkpoint written before the moduli were stored has none: they are fixed again at the
  // next step, from the restored state.
  if (const std::vector<double>* modulus = array(kSurfaceModulus, models_.size()))
    surface_contact_modulus_ = *modulus;
}

std::size_t Solver::bytes_per_particle() const {
  return Particles::bytes_per_particle() + sizeof(Stencil) + sizeof(double) +
         (settings_.volumetric_smoothing ? sizeof(SmoothedIncrement) : 0);
}

void Solver::fail_at_particle(std::size_t particle, const std::string& reason) const {
  const Vec2& x = particles_.position[particle];
  const int material = particles_.material[particle];
  throw Error(fmt::format(
      "MPM stopped in step {} at time {:.6g} s: particle {} (material {}, {}) at x = {:.6g} m, "
      "y = {:.6g} m: {}",
      steps_ + 1, time_, particle, material, models_[material]->name(), x.x(), x.y(), reason));
}

double Solver::step() {
  const double dt = next_time_step();
  advance(dt);
  return dt;
}

// One explicit step. Three passes over the particles: the grid update runs node by node in the
// node loop of the particles-to-grid scatter (as soon as a node's sums are complete), the MUSL
// remap in the grid-to-particles pass.
void Solver::advance(double dt) {
  const bool axisymmetric = settings_.geometry == Geometry::axisymmetric;
  const Vec2 gravity(0.0, -settings_.gravity_multiplier * settings_.gravity);
  // Weights at x^n -> particles to grid (mass, momentum, forces) -> grid update (damping,
  // dashpots, boundary conditions: v^L and Δv).
  const ParticlesToGrid to_grid(grid_, particles_, settings_.shape_function, axisymmetric,
                                settings_.mass_scaling, gravity, stencils_.data(),
                                start_radius_.data());
  // Surface contact: the penalty forces at the corners at x^n, as nodal forces of the update.
  const bool surface = settings_.contact == ContactScheme::surface;
  if (surface) apply_surface_contact(dt);
  const GridUpdate grid_update(grid_, settings_.local_damping, dashpot_x_, dashpot_y_,
                               node_motion_.data(), dt,
                               surface && !rigid_bodies_.empty() ? surface_force_.data() : nullptr);
  std::vector<GridUpdateTally>& grid_tallies = reset_tallies(grid_update_tallies_);
  scatter_.run(
      grid_, stencils_, ScatterSums::mass_momentum_force,
      [&](long p, NodeSums* sums, int) {
        to_grid.weights(p);
        to_grid.scatter(p, sums);
      },
      [&](long n, int thread) { grid_update.node(n, grid_tallies[thread]); });
  add_grid_update_tallies();
  // Contact: the rigid bodies correct v^L and Δv (Coulomb friction); the forces on the bodies.
  if (!surface) apply_contact(dt, ContactPass::after_grid_update);
  // XPIC(m > 1): the PIC share's target.
  if (xpic_active()) compute_xpic_shift();

  // Grid to particles (FLIP/PIC velocity, position) -> [MUSL: remap, each particle's new
  // momentum back to the grid with the same weights, the nodal velocities from it, and the
  // contact on these velocities, so that the strain rate sees no penetration].
  const GridToParticles to_particles(particles_, grid_, stencils_.data(), node_motion_.data(),
                                     xpic_active() ? xpic_shift_.data() : nullptr,
                                     settings_.flip_fraction, settings_.mass_scaling, axisymmetric,
                                     gravity, dt);
  std::vector<ParticleMotionTally>& motion_tallies = reset_tallies(particle_motion_tallies_);
  if (settings_.scheme == UpdateScheme::musl) {
    const MuslRemap remap(grid_, stencils_.data(), node_motion_.data());
    scatter_.run(
        grid_, stencils_, ScatterSums::momentum,
        [&](long p, NodeSums* sums, int thread) {
          remap.scatter(p, to_particles.move(p, motion_tallies[thread]), sums);
        },
        [&](long n, int) { remap.node(n); });
    if (!surface) apply_contact(dt, ContactPass::after_remap);
  } else {
    const auto count = static_cast<long>(particles_.size());
#pragma omp parallel num_threads(threads_)
    {
      ParticleMotionTally& tally = motion_tallies[omp_get_thread_num()];
#pragma omp for schedule(static)
      for (long p = 0; p < count; ++p) to_particles.move(p, tally);
    }
  }
  add_particle_motion_tallies();

  // Stress update: velocity gradient, Jaumann rotation, model update, F, volume, domain size.
  update_stress(dt);
  move_rigid_bodies(dt);
  time_ += dt;
  ++steps_;
}

void Solver::add_grid_update_tallies() {
  boundary_reaction_ = damping_force_ = Vec2::Zero();
  for (const GridUpdateTally& tally : grid_update_tallies_) {
    energies_.damping += tally.damping_work;
    energies_.absorbed += tally.absorbed_work;
    boundary_reaction_ += tally.reaction;
    damping_force_ += tally.damping_force;
  }
}

void Solver::add_particle_motion_tallies() {
  energies_.kinetic = 0.0;
  max_particle_speed_ = 0.0;
  ParticleFailure failure;
  for (const ParticleMotionTally& tally : particle_motion_tallies_) {
    energies_.external_work += tally.external_work;
    energies_.kinetic += tally.kinetic_energy;
    max_particle_speed_ = std::max(max_particle_speed_, tally.max_squared_speed);
    failure.merge(tally.failure);
  }
  max_particle_speed_ = std::sqrt(max_particle_speed_);
  if (failure.any()) fail_at_particle(failure.particle, failure.reason);
}

void Solver::move_rigid_bodies(double dt) {
  for (RigidBody& body : rigid_bodies_) body.translate(dt * body.velocity());
}

void Solver::update_dashpots() {
  dashpot_coefficients(grid_, settings_, dashpot_x_, dashpot_y_);
}

long Solver::run_until(double end_time) {
  long taken = 0;
  while (time_ < end_time) {
    const double full_step = next_time_step();
    const double remaining = end_time - time_;
    if (remaining <= 1e-9 * full_step) break;
    advance(std::min(full_step, remaining));
    ++taken;
  }
  return taken;
}

}  // namespace pilempm::mpm
