#include "pilempm/mpm/solver.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "pilempm/core/error.hpp"
#include "pilempm/mpm/in_plane_rotation.hpp"
#include "pilempm/mpm/thread_count.hpp"

namespace pilempm::mpm {

namespace {

// Visits the nodes of one particle's stencil with S_i, dS_i/dx, dS_i/dy at node index n. The
// usual 3 x 3 stencil runs as a fixed loop the compiler unrolls (no branch on the counts).
template <class NodeVisitor>
inline void for_each_node(const Stencil& stencil, int nx, NodeVisitor&& visit) {
  if (stencil.x.count == 3 && stencil.y.count == 3) {
    for (int j = 0; j < 3; ++j) {
      const int row = (stencil.y.first + j) * nx + stencil.x.first;
      const double weight_y = stencil.y.weight[j], gradient_y = stencil.y.gradient[j];
      for (int i = 0; i < 3; ++i) {
        visit(row + i, stencil.x.weight[i] * weight_y, stencil.x.gradient[i] * weight_y,
              stencil.x.weight[i] * gradient_y);
      }
    }
    return;
  }
  for (int j = 0; j < stencil.y.count; ++j) {
    const int row = (stencil.y.first + j) * nx + stencil.x.first;
    const double weight_y = stencil.y.weight[j], gradient_y = stencil.y.gradient[j];
    for (int i = 0; i < stencil.x.count; ++i) {
      visit(row + i, stencil.x.weight[i] * weight_y, stencil.x.gradient[i] * weight_y,
            stencil.x.weight[i] * gradient_y);
    }
  }
}

// Visits the rows of one particle's stencil: visit(first node of the row, node count, S_j(y),
// dS_j/dy), the count a compile-time 3 for the usual 3 x 3 stencil. Sums over a row first and then
// over the rows take fewer products than node by node.
template <class RowVisitor>
inline void for_each_row(const Stencil& stencil, int nx, RowVisitor&& visit) {
  if (stencil.x.count == 3 && stencil.y.count == 3) {
    for (int j = 0; j < 3; ++j) {
      visit((stencil.y.first + j) * nx + stencil.x.first, std::integral_constant<int, 3>{},
            stencil.y.weight[j], stencil.y.gradient[j]);
    }
    return;
  }
  for (int j = 0; j < stencil.y.count; ++j) {
    visit((stencil.y.first + j) * nx + stencil.x.first, stencil.x.count, stencil.y.weight[j],
          stencil.y.gradient[j]);
  }
}

inline double sign(double value) {
  return value > 0.0 ? 1.0 : (value < 0.0 ? -1.0 : 0.0);
}

// Local non-viscous damping (Cundall 1987) of one nodal force component: -α |f| sign(v).
inline double local_damping_force(double alpha, double force, double velocity) {
  return -alpha * std::abs(force) * sign(velocity);
}

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
  thread_grids_.resize(static_cast<std::size_t>(threads_));
  thread_accounts_.resize(static_cast<std::size_t>(threads_));
  const auto nodes = static_cast<std::size_t>(grid_.node_count());
  for (ThreadGrid& buffer : thread_grids_) buffer.sums.assign(nodes, NodeSums{});
  node_motion_.assign(nodes, NodeMotion{});

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

std::vector<Solver::ThreadAccount>& Solver::reset_thread_accounts() {
  for (ThreadAccount& account : thread_accounts_) account = ThreadAccount{};
  return thread_accounts_;
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

double Solver::next_time_step() {
  if (settings_.fixed_time_step > 0.0) return settings_.fixed_time_step;
  if (wave_speed_step_ < 0 || steps_ - wave_speed_step_ >= settings_.wave_speed_interval) {
    const auto count = static_cast<long>(particles_.size());
    const double mass_scaling = settings_.mass_scaling;
    double max_speed = 0.0;
#pragma omp parallel for num_threads(threads_) schedule(static) reduction(max : max_speed)
    for (long p = 0; p < count; ++p) {
      const double density = mass_scaling * particles_.mass[p] / particles_.volume[p];
      const double modulus = models_[particles_.material[p]]->wave_modulus(particles_.state[p]);
      max_speed = std::max(max_speed, std::sqrt(modulus / density));
    }
    max_wave_speed_ = max_speed;
    wave_speed_step_ = steps_;
  }
  const double speed = max_wave_speed_ + max_particle_speed_;
  if (!(speed > 0.0 && std::isfinite(speed)))
    throw Error(fmt::format("MPM: no finite wave speed for the time step in step {} ({} m/s)",
                            steps_ + 1, speed));
  return settings_.courant_number * grid_.min_spacing() / speed;
}

double Solver::step() {
  const double dt = next_time_step();
  advance(dt);
  return dt;
}

void Solver::advance(double dt) {
  particles_to_grid(dt);    // weights at x^n; nodal mass, momentum, forces; the grid update
  apply_contact(dt, true);  // rigid bodies: Coulomb frictional contact, forces on the bodies
  if (xpic_active()) compute_xpic_shift();
  grid_to_particles(dt);  // FLIP/PIC velocities and positions (MUSL: new momentum to the grid)
  update_stress(dt);      // velocity gradient, Jaumann rotation, model update, F, volume
  for (RigidBody& body : rigid_bodies_) body.translate(dt * body.velocity());
  time_ += dt;
  ++steps_;
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

// Scatter without locks: each thread adds into its own buffer, and then each node's sum is formed
// from the buffers in thread order (over the node range each thread touched), which also clears
// them. scatter_particle(p, sums, thread) adds particle p's share and leaves its stencil in
// stencils_; finish_node(n, thread) runs once node n's sums are complete.
template <class ScatterParticle, class FinishNode>
void Solver::scatter_to_grid(bool mass_and_force, ScatterParticle&& scatter_particle,
                             FinishNode&& finish_node) {
  NodalFields& nodes = grid_.nodes();
  const long node_count = grid_.node_count();
  const auto particle_count = static_cast<long>(particles_.size());
  const int nx = grid_.nx();
#pragma omp parallel num_threads(threads_)
  {
    const int thread = omp_get_thread_num();
    NodeSums* const sums = thread_grids_[static_cast<std::size_t>(thread)].sums.data();
    int lowest_node = static_cast<int>(node_count), end_node = 0;
#pragma omp for schedule(static)
    for (long p = 0; p < particle_count; ++p) {
      scatter_particle(p, sums, thread);
      const Stencil& stencil = stencils_[p];
      const int first = stencil.y.first * nx + stencil.x.first;
      lowest_node = std::min(lowest_node, first);
      end_node = std::max(end_node, first + (stencil.y.count - 1) * nx + stencil.x.count);
    }
    thread_grids_[static_cast<std::size_t>(thread)].lowest_node = lowest_node;
    thread_grids_[static_cast<std::size_t>(thread)].end_node = end_node;
#pragma omp barrier
    const int team = omp_get_num_threads();
#pragma omp for schedule(static)
    for (long n = 0; n < node_count; ++n) {
      Vec2 momentum = Vec2::Zero(), force = Vec2::Zero();
      double mass = 0.0;
      for (int t = 0; t < team; ++t) {
        ThreadGrid& buffer = thread_grids_[static_cast<std::size_t>(t)];
        if (n < buffer.lowest_node || n >= buffer.end_node) continue;
        NodeSums& node = buffer.sums[static_cast<std::size_t>(n)];
        momentum += node.momentum;
        node.momentum.setZero();
        if (mass_and_force) {
          mass += node.mass;
          force += node.force;
          node.mass = 0.0;
          node.force.setZero();
        }
      }
      nodes.momentum_x[n] = momentum.x();
      nodes.momentum_y[n] = momentum.y();
      if (mass_and_force) {
        nodes.mass[n] = mass;
        nodes.force_x[n] = force.x();
        nodes.force_y[n] = force.y();
      }
      finish_node(n, thread);
    }
  }
}

// Particles to grid and the grid update in one parallel pass: each node is updated as soon as
// its sums are complete (in the scatter's node loop, split like a loop of its own).
void Solver::particles_to_grid(double dt) {
  const Particles& p = particles_;
  const int nx = grid_.nx();
  const ShapeFunction shape = settings_.shape_function;
  const bool axisymmetric = settings_.geometry == Geometry::axisymmetric;
  const double mass_scaling = settings_.mass_scaling;
  const Vec2 gravity(0.0, -settings_.gravity_multiplier * settings_.gravity);
  NodalFields& nodes = grid_.nodes();
  const double* free_x = grid_.free_x().data();
  const double* free_y = grid_.free_y().data();
  const double alpha = settings_.local_damping;
  const bool absorbing = !settings_.absorbing_boundaries.empty();
  std::vector<ThreadAccount>& accounts = reset_thread_accounts();
  scatter_to_grid(
      true,
      [&](long i, NodeSums* to, int) {
        Stencil& stencil = stencils_[i];
        const Vec2& x = p.position[i];
        compute_stencil(grid_, shape, x.x(), x.y(), p.half_size[i].x(), p.half_size[i].y(),
                        stencil);
        if (axisymmetric) start_radius_[i] = x.x();

        const double inertial_mass = mass_scaling * p.mass[i];
        const Vec2 momentum = inertial_mass * p.velocity[i];
        const Vec2 body_force = p.mass[i] * gravity + p.external_force[i];
        const Vec6& stress = p.state[i].stress;
        const double volume = p.volume[i];
        const double v_sxx = volume * stress[k11], v_syy = volume * stress[k22];
        const double v_sxy = volume * stress[k12] / kSqrt2;
        // Axisymmetry: the hoop stress pulls the radial nodes by -V σ_θθ S_i / r_p.
        const double hoop_force = axisymmetric ? -volume * stress[k33] / x.x() : 0.0;
        const double radial_force = body_force.x() + hoop_force;
        for_each_row(stencil, nx, [&](int row, auto row_nodes, double weight_y, double gradient_y) {
          // f_i = S_i b_p - V_p σ_p ∇S_i with S_i = S_x S_y, ∇S_i = (S_x' S_y, S_x S_y'): per
          // row, the coefficients of S_x and S_x'.
          const double row_mass = weight_y * inertial_mass;
          const Vec2 row_momentum = weight_y * momentum;
          const Vec2 force_weight(weight_y * radial_force - gradient_y * v_sxy,
                                  weight_y * body_force.y() - gradient_y * v_syy);
          const Vec2 force_gradient(-weight_y * v_sxx, -weight_y * v_sxy);
          for (int k = 0; k < row_nodes; ++k) {
            NodeSums& node = to[row + k];
            const double weight_x = stencil.x.weight[k], gradient_x = stencil.x.gradient[k];
            node.mass += weight_x * row_mass;
            node.momentum += weight_x * row_momentum;
            node.force += weight_x * force_weight + gradient_x * force_gradient;
          }
        });
      },
      [&](long n, int thread) {
        // The grid update of node n: momentum balance with damping and boundary conditions.
        ThreadAccount& account = accounts[static_cast<std::size_t>(thread)];
        const double mass = nodes.mass[n];
        if (mass <= 0.0) {
          nodes.velocity_x[n] = nodes.velocity_y[n] = 0.0;
          nodes.velocity_change_x[n] = nodes.velocity_change_y[n] = 0.0;
          node_motion_[static_cast<std::size_t>(n)] = NodeMotion{};
          return;
        }
        const double vx = nodes.momentum_x[n] / mass, vy = nodes.momentum_y[n] / mass;
        // Local non-viscous damping: f_damped = f - α |f| sign(v), per free component. A held
        // component does not move, so it takes none: else the damping of the load a support
        // carries (α |f| with the sign of the velocity mapped from the particles) would enter the
        // support's reaction and the damping's energy.
        const double damping_x = free_x[n] * local_damping_force(alpha, nodes.force_x[n], vx);
        const double damping_y = free_y[n] * local_damping_force(alpha, nodes.force_y[n], vy);
        // v^L = v + f dt / m, then the boundary conditions; Δv over the step for FLIP. A dashpot
        // -C v^L (absorbing boundary) is taken implicitly: v^L = (m v + f dt) / (m + C dt).
        double new_vx = vx + (nodes.force_x[n] + damping_x) * dt / mass;
        double new_vy = vy + (nodes.force_y[n] + damping_y) * dt / mass;
        if (absorbing) {
          const double cx = dashpot_x_[n], cy = dashpot_y_[n];
          if (cx > 0.0) new_vx *= mass / (mass + cx * dt);
          if (cy > 0.0) new_vy *= mass / (mass + cy * dt);
          // Work of the dashpot force -C v^L over the step, with the mean velocity.
          account.sum[1] += 0.5 * dt * (cx * new_vx * (vx + new_vx) + cy * new_vy * (vy + new_vy));
        }
        // The constraint's force: what takes the free velocity to the held one.
        account.sum[2] += (1.0 - free_x[n]) * (-mass * new_vx / dt);
        account.sum[3] += (1.0 - free_y[n]) * (-mass * new_vy / dt);
        new_vx *= free_x[n];
        new_vy *= free_y[n];
        nodes.velocity_x[n] = new_vx;
        nodes.velocity_y[n] = new_vy;
        nodes.velocity_change_x[n] = new_vx - vx;
        nodes.velocity_change_y[n] = new_vy - vy;
        node_motion_[static_cast<std::size_t>(n)] = {Vec2(new_vx, new_vy),
                                                     Vec2(new_vx - vx, new_vy - vy)};
        // Work of the damping force over the step, with the mean of the old and new velocities.
        account.sum[0] -= 0.5 * dt * (damping_x * (vx + new_vx) + damping_y * (vy + new_vy));
        // The damping force on the soil.
        account.sum[4] += damping_x;
        account.sum[5] += damping_y;
      });
  boundary_reaction_ = damping_force_ = Vec2::Zero();
  for (const ThreadAccount& account : accounts) {
    energies_.damping += account.sum[0];
    energies_.absorbed += account.sum[1];
    boundary_reaction_ += Vec2(account.sum[2], account.sum[3]);
    damping_force_ += Vec2(account.sum[4], account.sum[5]);
  }
}

void Solver::update_dashpots() {
  const auto nodes = static_cast<std::size_t>(grid_.node_count());
  dashpot_x_.assign(settings_.absorbing_boundaries.empty() ? 0 : nodes, 0.0);
  dashpot_y_.assign(settings_.absorbing_boundaries.empty() ? 0 : nodes, 0.0);
  const bool axisymmetric = settings_.geometry == Geometry::axisymmetric;
  const GridAxis& x_axis = grid_.x_axis();
  const GridAxis& y_axis = grid_.y_axis();
  // The share of a side's length that node k of an axis carries: half of each adjacent cell.
  auto share = [](const GridAxis& axis, int k) {
    double length = 0.0;
    if (k > 0) length += 0.5 * axis.spacing(k - 1);
    if (k < axis.cell_count()) length += 0.5 * axis.spacing(k);
    return length;
  };
  for (const AbsorbingBoundary& boundary : settings_.absorbing_boundaries) {
    const double normal = boundary.density * boundary.p_wave_speed;
    const double tangential = boundary.density * boundary.s_wave_speed;
    const bool vertical_side = boundary.side == Side::left || boundary.side == Side::right;
    if (vertical_side) {
      const int i = boundary.side == Side::left ? 0 : grid_.nx() - 1;
      const double radius = axisymmetric ? x_axis.node(i) : 1.0;
      for (int j = 0; j < grid_.ny(); ++j) {
        const double area = share(y_axis, j) * radius;
        dashpot_x_[static_cast<std::size_t>(grid_.node_index(i, j))] += normal * area;
        dashpot_y_[static_cast<std::size_t>(grid_.node_index(i, j))] += tangential * area;
      }
    } else {
      const int j = boundary.side == Side::bottom ? 0 : grid_.ny() - 1;
      for (int i = 0; i < grid_.nx(); ++i) {
        // Per radian in axisymmetry: the ring of radius r_i over the node's share of the side
        // (exact for the integral of r over a linear hat would differ by O(h^2 / r)).
        const double area = share(x_axis, i) * (axisymmetric ? x_axis.node(i) : 1.0);
        dashpot_x_[static_cast<std::size_t>(grid_.node_index(i, j))] += tangential * area;
        dashpot_y_[static_cast<std::size_t>(grid_.node_index(i, j))] += normal * area;
      }
    }
  }
}

int Solver::add_rigid_body(RigidBody body) {
  const bool axisymmetric = settings_.geometry == Geometry::axisymmetric;
  if (body.axisymmetric() != axisymmetric)
    throw InvalidValue("rigid body", body.axisymmetric() ? "pile" : "polygon",
                       axisymmetric ? "a pile in axisymmetry" : "a polygon in plane strain");
  RigidBodyForce force;
  force.parts.assign(static_cast<std::size_t>(body.part_count()), Vec2::Zero());
  rigid_bodies_.push_back(std::move(body));
  rigid_body_forces_.push_back(std::move(force));
  return static_cast<int>(rigid_bodies_.size()) - 1;
}

// Rigid-body form of the multi-velocity contact of Bardenhagen, Brackbill & Sulsky (2000) and
// Bardenhagen et al. (2001): the body is a second velocity field of infinite mass, so the centre
// of mass velocity at a node is the body's. At a node with soil mass inside the body or closer
// than the contact distance (half the smallest cell by default: the nodes of the cell row that
// touches the surface, but not the next row) whose soil velocity approaches the body:
//   v_rel = v_i - v_body, v_n = v_rel . n < 0 (approaching; v_n >= 0 separates freely)
//   Δv = -v_n n - min(|v_t|, μ |v_n|) v_t / |v_t|, v_t = v_rel - v_n n   (Coulomb: stick or slip)
// At a node with one constrained component (the axis, a roller) the free component alone meets
// v_rel . n = 0, without friction; a node with both constrained is left alone. The force on the
// body is -Σ_i m_i Δv_i / Δt, in total and per surface part of the nearest surface point.
// The nodes are visited serially over the body's bounding box, so the sums are deterministic.
void Solver::apply_contact(double dt, bool forces) {
  if (rigid_bodies_.empty()) return;
  NodalFields& nodes = grid_.nodes();
  const double* free_x = grid_.free_x().data();
  const double* free_y = grid_.free_y().data();
  const GridAxis& x_axis = grid_.x_axis();
  const GridAxis& y_axis = grid_.y_axis();
  const int nx = grid_.nx();
  const double alpha = settings_.local_damping;
  for (std::size_t b = 0; b < rigid_bodies_.size(); ++b) {
    const RigidBody& body = rigid_bodies_[b];
    RigidBodyForce& force = rigid_body_forces_[b];
    if (forces) {
      force.total.setZero();
      for (Vec2& part : force.parts) part.setZero();
    }
    const double reach =
        body.contact_distance() > 0.0 ? body.contact_distance() : 0.5 * grid_.min_spacing();
    const Vec2 low = body.box_min() - Vec2::Constant(reach);
    const Vec2 high = body.box_max() + Vec2::Constant(reach);
    if (high.x() < x_axis.start() || low.x() > x_axis.end() || high.y() < y_axis.start() ||
        low.y() > y_axis.end())
      continue;
    const int i_first = x_axis.cell_of(low.x()), i_last = x_axis.cell_of(high.x()) + 1;
    const int j_first = y_axis.cell_of(low.y()), j_last = y_axis.cell_of(high.y()) + 1;
    const Vec2& body_velocity = body.velocity();
    const double friction = body.friction();
    for (int j = j_first; j <= j_last; ++j) {
      for (int i = i_first; i <= i_last; ++i) {
        const int n = j * nx + i;
        const double mass = nodes.mass[n];
        if (mass <= 0.0) continue;
        const SurfaceQuery surface = body.query(Vec2(x_axis.node(i), y_axis.node(j)));
        if (surface.distance >= reach) continue;
        double damped_work = 0.0;
        // The local damping of the grid update does not act at a contact node: the body sets its
        // velocity, as a support does (else the damping force would add to the contact force,
        // by about the factor 1 + α). Its share of v^L is taken out again (not at dashpots).
        Vec2 damping_change = Vec2::Zero();
        if (forces && alpha > 0.0 &&
            (dashpot_x_.empty() || (dashpot_x_[n] == 0.0 && dashpot_y_[n] == 0.0))) {
          const Vec2 old_velocity = Vec2(nodes.momentum_x[n], nodes.momentum_y[n]) / mass;
          const Vec2 damping_force(local_damping_force(alpha, nodes.force_x[n], old_velocity.x()),
                                   local_damping_force(alpha, nodes.force_y[n], old_velocity.y()));
          damping_change =
              Vec2(free_x[n] * damping_force.x(), free_y[n] * damping_force.y()) * (dt / mass);
          damped_work =
              -0.5 * dt *
              damping_force.dot(old_velocity + Vec2(nodes.velocity_x[n], nodes.velocity_y[n]));
        }
        const Vec2 undamped = Vec2(nodes.velocity_x[n], nodes.velocity_y[n]) - damping_change;
        const Vec2 relative = undamped - body_velocity;
        const double normal_speed = relative.dot(surface.normal);
        if (normal_speed >= 0.0) continue;  // separating or sliding along: no contact
        Vec2 change = Vec2::Zero();
        if (free_x[n] > 0.0 && free_y[n] > 0.0) {
          const Vec2 tangential = relative - normal_speed * surface.normal;
          const double slip = tangential.norm();
          change = -normal_speed * surface.normal;  // the body's normal velocity wins
          // Coulomb: the tangential correction is at most μ times the normal one (stick below).
          if (slip > 0.0) change -= std::min(slip, -friction * normal_speed) / slip * tangential;
        } else if (free_x[n] > 0.0 || free_y[n] > 0.0) {
          // One free component (the axis, a roller): it alone stops the approach, v_rel . n = 0,
          // without friction; a normal across the free direction is held by the constraint.
          const Vec2 free_direction = free_x[n] > 0.0 ? Vec2(1.0, 0.0) : Vec2(0.0, 1.0);
          const double along = free_direction.dot(surface.normal);
          if (std::abs(along) > 1e-3) change = -normal_speed / along * free_direction;
        }
        nodes.velocity_x[n] = undamped.x() + change.x();
        nodes.velocity_y[n] = undamped.y() + change.y();
        node_motion_[static_cast<std::size_t>(n)].velocity += change - damping_change;
        if (forces) {
          nodes.velocity_change_x[n] += change.x() - damping_change.x();
          nodes.velocity_change_y[n] += change.y() - damping_change.y();
          node_motion_[static_cast<std::size_t>(n)].change += change - damping_change;
          energies_.damping -= damped_work;
          damping_force_ -= damping_change * (mass / dt);  // the contact took it out
          const Vec2 on_body = -mass * change / dt;
          force.total += on_body;
          force.parts[static_cast<std::size_t>(surface.part)] += on_body;
          // The work of the body on the soil: its force on the soil along its own velocity.
          energies_.contact_work -= on_body.dot(body_velocity) * dt;
        }
      }
    }
  }
}

// XPIC(m) (Hammerquist & Nairn 2017, "A new method for material point method particle updates
// that reduces noise and enhances stability"). With the particle-to-grid map S+ (mass-weighted)
// and the grid-to-particle map S, PIC sets V^n+1 = S v^L = S S+ V^n + S Δv. XPIC(m) replaces the
// smoothing S S+ by 1 - (1 - S S+)^m, which on the grid is S v* with
//   v* = Σ_k=1..m (-1)^(k+1) C(m, k) (S+ S)^(k-1) v^n,  v^n = S+ V^n (the grid velocity before
// the update). m = 1 gives PIC; as m grows, only the null space of S+ (the noise) is removed.
// Each power of S+ S is one gather to the particles and one mass-weighted scatter back, with the
// boundary conditions of the grid applied after each. The coefficients sum to 1, so a rigid
// translation is kept. The nodal momentum is used as the scatter's buffer and restored after.
void Solver::compute_xpic_shift() {
  NodalFields& nodes = grid_.nodes();
  const auto node_count = static_cast<std::size_t>(grid_.node_count());
  const double* free_x = grid_.free_x().data();
  const double* free_y = grid_.free_y().data();
  const int nx = grid_.nx();
  const int order = settings_.xpic_order;
  const double mass_scaling = settings_.mass_scaling;
  xpic_start_.resize(node_count);
  xpic_power_.resize(node_count);
  xpic_shift_.resize(node_count);
  Vec2* start = xpic_start_.data();
  Vec2* power = xpic_power_.data();
  Vec2* sum = xpic_shift_.data();  // Σ c_k (S+ S)^(k-1) v^n, turned into the shift at the end
  const auto nodes_long = static_cast<long>(node_count);
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (long n = 0; n < nodes_long; ++n) {
    const double mass = nodes.mass[n];
    const Vec2 velocity =
        mass > 0.0 ? Vec2(nodes.momentum_x[n] / mass, nodes.momentum_y[n] / mass) : Vec2::Zero();
    start[n] = velocity;
    power[n] = Vec2(free_x[n] * velocity.x(), free_y[n] * velocity.y());
    sum[n] = order * power[n];  // c_1 = m
  }
  double coefficient = order;
  for (int k = 2; k <= order; ++k) {
    // c_k = (-1)^(k+1) C(m, k) = -c_(k-1) (m - k + 1) / k
    coefficient = -coefficient * (order - k + 1) / k;
    scatter_to_grid(
        false,
        [&](long i, NodeSums* to, int) {
          Vec2 velocity = Vec2::Zero();
          for_each_node(stencils_[i], nx,
                        [&](int n, double s, double, double) { velocity += s * power[n]; });
          const Vec2 momentum = mass_scaling * particles_.mass[i] * velocity;
          for_each_node(stencils_[i], nx,
                        [&](int n, double s, double, double) { to[n].momentum += s * momentum; });
        },
        [&](long n, int) {
          const double mass = nodes.mass[n];
          const double inverse_mass = mass > 0.0 ? 1.0 / mass : 0.0;
          power[n] = Vec2(free_x[n] * nodes.momentum_x[n] * inverse_mass,
                          free_y[n] * nodes.momentum_y[n] * inverse_mass);
          sum[n] += coefficient * power[n];
        });
  }
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (long n = 0; n < nodes_long; ++n) {
    const double mass = nodes.mass[n];
    nodes.momentum_x[n] = mass * start[n].x();
    nodes.momentum_y[n] = mass * start[n].y();
    sum[n] = Vec2(free_x[n] * (sum[n].x() - start[n].x()), free_y[n] * (sum[n].y() - start[n].y()));
  }
}

void Solver::grid_to_particles(double dt) {
  Particles& p = particles_;
  const NodeMotion* motion = node_motion_.data();
  const auto count = static_cast<long>(p.size());
  const int nx = grid_.nx();
  const double flip = settings_.flip_fraction;
  const double mass_scaling = settings_.mass_scaling;
  const bool axisymmetric = settings_.geometry == Geometry::axisymmetric;
  const Vec2 gravity(0.0, -settings_.gravity_multiplier * settings_.gravity);
  std::vector<ThreadAccount>& accounts = reset_thread_accounts();
  const Vec2* xpic_shift = xpic_active() ? xpic_shift_.data() : nullptr;
  // Updates particle i from the grid and returns its new momentum.
  auto move_particle = [&](long i, ThreadAccount& account) -> Vec2 {
    Vec2 grid_velocity = Vec2::Zero(), velocity_change = Vec2::Zero();
    for_each_node(stencils_[i], nx, [&](int n, double s, double, double) {
      const NodeMotion& node = motion[n];
      grid_velocity += s * node.velocity;
      velocity_change += s * node.change;
    });
    // The PIC share's target: the grid velocity, with XPIC(m) shifted by S (v* - v^n).
    Vec2 pic_velocity = grid_velocity;
    if (xpic_shift)
      for_each_node(stencils_[i], nx,
                    [&](int n, double s, double, double) { pic_velocity += s * xpic_shift[n]; });
    // FLIP/PIC blend of the particle velocity; the particle moves with the grid velocity.
    p.velocity[i] = flip * (p.velocity[i] + velocity_change) + (1.0 - flip) * pic_velocity;
    const Vec2 displacement = dt * grid_velocity;
    account.sum[0] += (p.mass[i] * gravity + p.external_force[i]).dot(displacement);
    p.position[i] += displacement;
    const double inertial_mass = mass_scaling * p.mass[i];
    // |v|^2: the largest speed is the root of the largest square (taken after the loop).
    const double squared_speed = p.velocity[i].squaredNorm();
    account.sum[1] += 0.5 * inertial_mass * squared_speed;
    account.max = std::max(account.max, squared_speed);
    const Vec2& x = p.position[i];
    if (!(p.velocity[i].allFinite() && grid_.contains(x.x(), x.y()) &&
          (!axisymmetric || x.x() > 0.0)) &&
        static_cast<std::size_t>(i) < account.failed_particle) {
      account.failed_particle = static_cast<std::size_t>(i);
      account.failure =
          "the particle left the grid (or reached r <= 0) or its velocity is not "
          "finite";
    }
    return inertial_mass * p.velocity[i];
  };

  if (settings_.scheme == UpdateScheme::musl) {
    // MUSL: the new particle momentum goes straight back to the grid, with the same weights.
    NodalFields& grid_nodes = grid_.nodes();
    const double* free_x = grid_.free_x().data();
    const double* free_y = grid_.free_y().data();
    scatter_to_grid(
        false,
        [&](long i, NodeSums* to, int thread) {
          const Vec2 momentum = move_particle(i, accounts[thread]);
          for_each_node(stencils_[i], nx,
                        [&](int n, double s, double, double) { to[n].momentum += s * momentum; });
        },
        [&](long n,
            int) {  // the nodal velocity from the new momentum, with the boundary conditions
          const double mass = grid_nodes.mass[n];
          const double inverse_mass = mass > 0.0 ? 1.0 / mass : 0.0;
          const double vx = free_x[n] * grid_nodes.momentum_x[n] * inverse_mass;
          const double vy = free_y[n] * grid_nodes.momentum_y[n] * inverse_mass;
          grid_nodes.velocity_x[n] = vx;
          grid_nodes.velocity_y[n] = vy;
          node_motion_[static_cast<std::size_t>(n)].velocity = Vec2(vx, vy);
        });
    // The remapped velocities obey the contact too, so the strain rate sees no penetration.
    apply_contact(dt, false);
  } else {
#pragma omp parallel num_threads(threads_)
    {
      ThreadAccount& account = accounts[omp_get_thread_num()];
#pragma omp for schedule(static)
      for (long i = 0; i < count; ++i) move_particle(i, account);
    }
  }

  energies_.kinetic = 0.0;
  max_particle_speed_ = 0.0;
  std::size_t failed = kNoParticle;
  const char* failure = "";
  for (const ThreadAccount& account : accounts) {
    energies_.external_work += account.sum[0];
    energies_.kinetic += account.sum[1];
    max_particle_speed_ = std::max(max_particle_speed_, account.max);
    if (account.failed_particle < failed) {
      failed = account.failed_particle;
      failure = account.failure;
    }
  }
  max_particle_speed_ = std::sqrt(max_particle_speed_);
  if (failed != kNoParticle) fail_at_particle(failed, failure);
}

// Volumetric-locking remedy: within each grid cell, the volumetric strain increments of the
// particles (by their position after the move) are replaced by their mean weighted by the
// particle volumes, Δε̄_v = Σ V_p Δε_v,p / Σ V_p; the deviatoric parts are kept. The difference
// goes equally to the in-plane normal components in plane strain (the out-of-plane strain stays
// zero) and to the three normal components in axisymmetry. Σ V Δε_v over a cell is unchanged, so
// the volume of the cell's particles changes as without smoothing. The sums per cell run
// serially in particle order (deterministic for any thread count).
template <class Kinematics>
void Solver::smooth_volumetric_increments(Kinematics&& kinematics) {
  const Particles& p = particles_;
  const auto count = static_cast<long>(p.size());
  const bool axisymmetric = settings_.geometry == Geometry::axisymmetric;
  const GridAxis& x_axis = grid_.x_axis();
  const GridAxis& y_axis = grid_.y_axis();
  const int cells_x = x_axis.cell_count();
  smoothed_.resize(p.size());
  cell_volume_.assign(static_cast<std::size_t>(cells_x * y_axis.cell_count()), 0.0);
  cell_strain_.assign(cell_volume_.size(), 0.0);
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (long i = 0; i < count; ++i) {
    SmoothedIncrement& smoothed = smoothed_[i];
    kinematics(i, smoothed.increment, smoothed.hoop_increment);
    const Vec2& x = p.position[i];
    smoothed.cell = y_axis.cell_of(x.y()) * cells_x + x_axis.cell_of(x.x());
  }
  for (std::size_t i = 0; i < p.size(); ++i) {
    const SmoothedIncrement& smoothed = smoothed_[i];
    const double volumetric = smoothed.increment.trace() + smoothed.hoop_increment;
    cell_volume_[smoothed.cell] += p.volume[i];
    cell_strain_[smoothed.cell] += p.volume[i] * volumetric;
  }
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (long i = 0; i < count; ++i) {
    SmoothedIncrement& smoothed = smoothed_[i];
    const double mean = cell_strain_[smoothed.cell] / cell_volume_[smoothed.cell];
    const double difference = mean - (smoothed.increment.trace() + smoothed.hoop_increment);
    const double share = difference / (axisymmetric ? 3.0 : 2.0);
    smoothed.increment(0, 0) += share;
    smoothed.increment(1, 1) += share;
    if (axisymmetric) smoothed.hoop_increment += share;
  }
}

void Solver::update_stress(double dt) {
  Particles& p = particles_;
  const auto count = static_cast<long>(p.size());
  const int nx = grid_.nx();
  const bool axisymmetric = settings_.geometry == Geometry::axisymmetric;
  const bool stretch_domains = settings_.shape_function == ShapeFunction::cpgimp;
  const bool smoothing = settings_.volumetric_smoothing;
  // Kinematics of particle i over the step: the in-plane increment L dt, with the velocity
  // gradient L_ab = Σ v_ia dS_i/dx_b, and the hoop increment v_r dt / r (axisymmetry).
  const NodeMotion* motion = node_motion_.data();
  auto kinematics = [&](long i, Mat2& increment, double& hoop_increment) {
    const Stencil& stencil = stencils_[i];
    double dvx_dx = 0.0, dvx_dy = 0.0, dvy_dx = 0.0, dvy_dy = 0.0, radial_velocity = 0.0;
    for_each_row(stencil, nx, [&](int row, auto row_nodes, double weight_y, double gradient_y) {
      // Along the row: Σ S_x' v and Σ S_x v; then times S_y or S_y'.
      Vec2 gradient_v = Vec2::Zero(), weight_v = Vec2::Zero();
      for (int k = 0; k < row_nodes; ++k) {
        const Vec2& v = motion[row + k].velocity;
        gradient_v += stencil.x.gradient[k] * v;
        weight_v += stencil.x.weight[k] * v;
      }
      dvx_dx += weight_y * gradient_v.x();
      dvx_dy += gradient_y * weight_v.x();
      dvy_dx += weight_y * gradient_v.y();
      dvy_dy += gradient_y * weight_v.y();
      radial_velocity += weight_y * weight_v.x();
    });
    increment << dt * dvx_dx, dt * dvx_dy, dt * dvy_dx, dt * dvy_dy;
    hoop_increment = axisymmetric ? dt * radial_velocity / start_radius_[i] : 0.0;
  };
  if (smoothing) smooth_volumetric_increments(kinematics);

  std::vector<ThreadAccount>& accounts = reset_thread_accounts();
#pragma omp parallel num_threads(threads_)
  {
    ThreadAccount& account = accounts[omp_get_thread_num()];
#pragma omp for schedule(static)
    for (long i = 0; i < count; ++i) {
      Mat2 increment;
      double hoop_increment;
      if (smoothing) {
        increment = smoothed_[i].increment;
        hoop_increment = smoothed_[i].hoop_increment;
      } else {
        kinematics(i, increment, hoop_increment);
      }
      Vec6 strain_increment;
      strain_increment << increment(0, 0), increment(1, 1), hoop_increment, 0.0, 0.0,
          kSqrt2 * 0.5 * (increment(0, 1) + increment(1, 0));

      // Jaumann rate: rotate the state by the spin increment W = skew(L) dt (about z), then
      // update it with the strain increment.
      MaterialState& state = p.state[i];
      const double spin = 0.5 * (increment(1, 0) - increment(0, 1));
      if (spin != 0.0) rotate_state_about_z(state, spin);
      const Vec6 stress_before = state.stress;
      const UpdateResult result = models_[p.material[i]]->update(state, strain_increment);
      if (!result.ok) {
        if (static_cast<std::size_t>(i) < account.failed_particle) {
          account.failed_particle = static_cast<std::size_t>(i);
          account.failure = result.message;
        }
        continue;
      }

      // F <- (I + L dt) F; F_33 <- (1 + Δε_θθ) F_33; V = det F V_0.
      Mat2& deformation = p.deformation_gradient[i];
      deformation = (Mat2::Identity() + increment) * deformation;
      p.out_of_plane_stretch[i] *= 1.0 + hoop_increment;
      const double volume_before = p.volume[i];
      const double jacobian = deformation.determinant();
      p.volume[i] = jacobian * p.out_of_plane_stretch[i] * p.initial_volume[i];
      // Strain work with the mean stress and mean volume over the step (trapezoidal rule).
      account.sum[0] += 0.25 * (volume_before + p.volume[i]) *
                        (stress_before + state.stress).dot(strain_increment);

      if (stretch_domains) {
        // cpGIMP: the domain's half-lengths follow the stretch V = sqrt(F F^T) along x and y
        // (2x2 square root: sqrt(B) = (B + sqrt(det B) I) / sqrt(tr B + 2 sqrt(det B))).
        const Mat2 left_cauchy_green = deformation * deformation.transpose();
        const double root_det = std::abs(jacobian);
        const double scale = 1.0 / std::sqrt(left_cauchy_green.trace() + 2.0 * root_det);
        p.half_size[i] =
            p.initial_half_size[i].cwiseProduct(Vec2((left_cauchy_green(0, 0) + root_det) * scale,
                                                     (left_cauchy_green(1, 1) + root_det) * scale));
      }
    }
  }
  std::size_t failed = kNoParticle;
  const char* failure = "";
  for (const ThreadAccount& account : accounts) {
    energies_.internal += account.sum[0];
    if (account.failed_particle < failed) {
      failed = account.failed_particle;
      failure = account.failure;
    }
  }
  if (failed != kNoParticle)
    fail_at_particle(failed, fmt::format("the stress update failed: {}", failure));
}

}  // namespace pilempm::mpm
