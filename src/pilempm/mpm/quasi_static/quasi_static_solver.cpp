#include "pilempm/mpm/quasi_static/quasi_static_solver.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "pilempm/core/error.hpp"
#include "pilempm/core/number_text.hpp"
#include "pilempm/mpm/quasi_static/step_data.hpp"

namespace pilempm::mpm::quasi_static {

using namespace detail;

namespace {

// Bisection on a segment's parameter s between `inside` (where is_inside(s) holds) and `outside`
// (where it does not): 60 halvings take it to round-off; returns the end that is outside.
template <class IsInside>
double last_outside(double inside, double outside, const IsInside& is_inside) {
  for (int k = 0; k < 60; ++k) {
    const double middle = 0.5 * (inside + outside);
    (is_inside(middle) ? inside : outside) = middle;
  }
  return outside;
}

// The contact counts of an iteration record: the points in contact and slipping at `now`, and
// those whose state changed from `was` (none when `was` is null: the start of an increment).
IterationRecord contact_record(const std::vector<PointContact>& now,
                               const std::vector<PointContact>* was) {
  IterationRecord record;
  for (std::size_t c = 0; c < now.size(); ++c) {
    record.contact_points += now[c].active ? 1 : 0;
    record.slipping_points += now[c].slip ? 1 : 0;
    if (was != nullptr && (now[c].active != (*was)[c].active || now[c].slip != (*was)[c].slip))
      ++record.contact_changes;
  }
  return record;
}

}  // namespace

void Settings::validate() const {
  auto positive = [](double value, const char* key) {
    if (!(value > 0.0) || !std::isfinite(value))
      throw InvalidValue(key, format_value(value), "> 0");
  };
  if (!(gravity >= 0.0) || !std::isfinite(gravity))
    throw InvalidValue("gravity", format_value(gravity), ">= 0");
  positive(force_tolerance, "force_tolerance");
  positive(energy_tolerance, "energy_tolerance");
  positive(perturbation, "perturbation");
  positive(floor_stiffness, "floor_stiffness");
  if (!(low_stress_stiffness >= 0.0) || !std::isfinite(low_stress_stiffness))
    throw InvalidValue("low_stress_stiffness", format_value(low_stress_stiffness), ">= 0");
  positive(low_stress_pressure, "low_stress_pressure");
  double previous_share = 1.0;
  for (const double share : low_stress_continuation) {
    if (!(share > 0.0 && share < previous_share))
      throw InvalidValue("low_stress_continuation", format_value(share),
                         fmt::format("in (0, {:g}): decreasing shares below 1", previous_share));
    previous_share = share;
  }
  if (max_iterations < 1)
    throw InvalidValue("max_iterations", std::to_string(max_iterations), ">= 1");
  if (line_search_steps < 0)
    throw InvalidValue("line_search_steps", std::to_string(line_search_steps), ">= 0");
  if (!(step_limit >= 0.0) || !std::isfinite(step_limit))
    throw InvalidValue("step_limit", format_value(step_limit), ">= 0");
  if (max_cuts < 0) throw InvalidValue("max_cuts", std::to_string(max_cuts), ">= 0");
  if (!(accept_tolerance >= 0.0 && accept_tolerance < 1.0))
    throw InvalidValue("accept_tolerance", format_value(accept_tolerance), "[0, 1)");
  if (accept_after < 0) throw InvalidValue("accept_after", std::to_string(accept_after), ">= 0");
  if (stall_iterations < 0)
    throw InvalidValue("stall_iterations", std::to_string(stall_iterations), ">= 0");
  if (!(tangent_reuse >= 0.0 && tangent_reuse <= 0.5))  // the case files' range
    throw InvalidValue("tangent_reuse", format_value(tangent_reuse), "in [0, 0.5]");
  if (easy_iterations < 0)
    throw InvalidValue("easy_iterations", std::to_string(easy_iterations), ">= 0");
  if (!(support_threshold >= 0.0 && support_threshold < 1.0))
    throw InvalidValue("support_threshold", format_value(support_threshold), "in [0, 1)");
  if (!(ghost_stiffness >= 0.0) || !std::isfinite(ghost_stiffness))
    throw InvalidValue("ghost_stiffness", format_value(ghost_stiffness), ">= 0");
  if (support_particles < 0)
    throw InvalidValue("support_particles", std::to_string(support_particles), ">= 0");
  if (!(inside_body_weakness >= 0.0 && inside_body_weakness <= 1.0))
    throw InvalidValue("inside_body_weakness", format_value(inside_body_weakness), "in [0, 1]");
  if (!(floor_volume_ratio == 0.0 || floor_volume_ratio > 1.0) ||
      !std::isfinite(floor_volume_ratio))
    throw InvalidValue("floor_volume_ratio", format_value(floor_volume_ratio), "0 (none) or > 1");
  if (threads < 0) throw InvalidValue("threads", std::to_string(threads), ">= 0");
  require_linear_solver(linear_solver);
  contact.validate();
}

QuasiStaticSolver::QuasiStaticSolver(Grid grid, Particles particles,
                                     std::vector<ModelPtr> materials, Settings settings)
    : grid_(std::move(grid)),
      particles_(std::move(particles)),
      materials_(std::move(materials)),
      settings_(settings) {
  settings_.validate();
  linear_solver_.set_kind(settings_.linear_solver);
  threads_ = settings_.threads > 0 ? settings_.threads : omp_get_max_threads();
  const bool axisymmetric = settings_.geometry == Geometry::axisymmetric;
  if (axisymmetric && grid_.x_axis().start() < 0.0)
    throw InvalidValue("grid x start", format_value(grid_.x_axis().start()), ">= 0 in axisymmetry");
  if (axisymmetric && grid_.x_axis().start() == 0.0) grid_.set_axis_of_symmetry(true);
  for (std::size_t p = 0; p < particles_.size(); ++p) {
    const auto what = [&](const char* field) { return fmt::format("particle {} {}", p, field); };
    const int material = particles_.material[p];
    if (material < 0 || material >= static_cast<int>(materials_.size()) ||
        !materials_[std::size_t(material)])
      throw InvalidValue(what("material"), std::to_string(material),
                         fmt::format("a model index in [0, {})", materials_.size()));
    if (!(particles_.volume[p] > 0.0))
      throw InvalidValue(what("volume"), format_value(particles_.volume[p]), "> 0");
    const Vec2& x = particles_.position[p];
    if (!grid_.contains(x.x(), x.y()))
      throw InvalidValue(what("position"), fmt::format("({}, {})", x.x(), x.y()),
                         "inside the grid");
    if (axisymmetric && !(x.x() > 0.0))
      throw InvalidValue(what("radius"), format_value(x.x()), "> 0 in axisymmetry");
  }
  contact_history_.assign(particles_.size() * kCorners, ContactHistory{});
  corner_position_.resize(particles_.size() * kCorners);
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    const Vec2& l = particles_.half_size[i];
    for (int q = 0; q < kCorners; ++q)
      corner_position_[i * kCorners + std::size_t(q)] =
          particles_.position[i] + Vec2((q & 1) ? l.x() : -l.x(), (q & 2) ? l.y() : -l.y());
  }
  node_displacement_.assign(std::size_t(grid_.node_count()), Vec2::Zero());
  contact_modulus_.assign(materials_.size(), 0.0);
}

void QuasiStaticSolver::bound_corners() {
  const GridAxis& x_axis = grid_.x_axis();
  const GridAxis& y_axis = grid_.y_axis();
  std::vector<detail::RoundedSurface> surfaces;
  for (const RigidBody& body : bodies_)
    surfaces.emplace_back(body, settings_.contact.vertex_radius * grid_.min_spacing());
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    const Vec2& x = particles_.position[i];
    // |l|: the half-diagonal of the domain, which holds its corners whatever its rotation.
    const double reach = particles_.half_size[i].norm();
    const Vec2 bound(std::min(reach, x_axis.spacing(x_axis.cell_of(x.x()))),
                     std::min(reach, y_axis.spacing(y_axis.cell_of(x.y()))));
    for (int q = 0; q < kCorners; ++q) {
      Vec2& corner = corner_position_[i * kCorners + std::size_t(q)];
      const Vec2 offset = corner - x;
      // The offset scaled towards the particle until both components are within the bound (a
      // point within it, to a relative 1e-12, does not move, so bounding again changes nothing).
      double scale = 1.0;
      for (int a = 0; a < 2; ++a)
        if (std::abs(offset[a]) > bound[a] * (1.0 + 1.0e-12))
          scale = std::min(scale, bound[a] / std::abs(offset[a]));
      if (scale == 1.0) continue;
      // Never deeper into a body than the point was (nor into one it was outside of): the
      // smallest scale in [scale, 1] at which it is not, by bisection.
      for (const detail::RoundedSurface& surface : surfaces) {
        const double floor = std::min(surface.query(corner).distance, 0.0);
        const auto too_deep = [&](double s) {
          return surface.query(x + s * offset).distance < floor;
        };
        if (too_deep(scale)) scale = last_outside(scale, 1.0, too_deep);
      }
      corner = x + scale * offset;
    }
  }
}

int QuasiStaticSolver::add_rigid_body(RigidBody body) {
  const bool axisymmetric = settings_.geometry == Geometry::axisymmetric;
  if (body.axisymmetric() != axisymmetric)
    throw InvalidValue("rigid body", body.axisymmetric() ? "pile" : "polygon",
                       axisymmetric ? "a pile in axisymmetry" : "a polygon in plane strain");
  // A body put where particles are (a pile wished in place) has the corners of the particles
  // next to it inside it, up to half a particle deep: their penalty forces would be of the order
  // of the modulus instead of the stress. Such contact points start on the surface instead, free
  // of strain and force (as an initial overclosure is adjusted in finite element contact): moved
  // along the surface's normal to its nearest point. (Drawing them along the segment to their
  // particle's centre instead made the quick case's load-test capacity move by 11 % from D/6 to
  // D/8, against 2.7 % with the normal; docs/quasi-static.md, "The placement at a
  // wished-in-place body and the mesh".) bound_corners never draws a point deeper into a body than
  // it was, so a point placed on the surface stays outside.
  for (Vec2& corner : corner_position_) {
    const SurfaceQuery hit = body.query(corner);
    if (hit.distance < 0.0) corner -= hit.distance * hit.normal;
  }
  BodyForce force;
  force.parts.assign(std::size_t(body.part_count()), Vec2::Zero());
  bodies_.push_back(std::move(body));
  body_forces_.push_back(std::move(force));
  return rigid_body_count() - 1;
}

void QuasiStaticSolver::set_material(int index, ModelPtr model) {
  if (index < 0 || index >= static_cast<int>(materials_.size()) || !model)
    throw InvalidValue("material index", std::to_string(index),
                       fmt::format("[0, {}) and a model", materials_.size()));
  materials_[std::size_t(index)] = std::move(model);
}

double energy_tolerance_for(double force_tolerance) {
  return with_significant_digits(100.0 * force_tolerance * force_tolerance, 9);
}

QuasiStaticSolver::Targets QuasiStaticSolver::targets(double fraction, const LoadStep& load) const {
  Targets t;
  t.gravity = gravity_multiplier_ + fraction * (load.gravity_multiplier - gravity_multiplier_);
  t.traction = traction_multiplier_ + fraction * (load.traction_multiplier - traction_multiplier_);
  t.body_step.assign(bodies_.size(), Vec2::Zero());
  for (std::size_t b = 0; b < bodies_.size() && b < load.body_displacement.size(); ++b)
    t.body_step[b] = fraction * load.body_displacement[b];
  return t;
}

std::vector<double> QuasiStaticSolver::prediction(const StepSetup& setup,
                                                  const std::vector<Vec2>& body_step) const {
  const double body_motion = largest_motion(body_step).norm();
  if (!settings_.predictor || !(body_motion > 0.0) || !(last_body_step_ > 0.0)) return {};
  const double scale = body_motion / last_body_step_;
  std::vector<double> predicted(std::size_t(setup.unknowns), 0.0);
  for (std::size_t c = 0; c < setup.dof.size(); ++c)
    if (setup.dof[c] >= 0)
      predicted[std::size_t(setup.dof[c])] = scale * node_displacement_[c / 2][int(c % 2)];
  return predicted;
}

std::string QuasiStaticSolver::failed_update(const Trial& trial) const {
  if (trial.failed_particle < 0) return "";
  const std::size_t i = std::size_t(trial.failed_particle);
  return fmt::format(" (particle {} at x = {:.6g} m, y = {:.6g} m: {})", i,
                     particles_.position[i].x(), particles_.position[i].y(), trial.failure);
}

bool QuasiStaticSolver::solve_sub_increment(double fraction, const LoadStep& load,
                                            SubIncrementRecord& record, LoadStepResult& result) {
  // The sub-increment's targets, linear in the fraction of the step from the current state.
  const Targets target = targets(fraction, load);
  const double gravity = target.gravity, traction = target.traction;
  const std::vector<Vec2>& body_step = target.body_step;

  StepSetup setup;
  build_setup(setup);
  result.unknowns = setup.unknowns;
  std::vector<double> du(std::size_t(setup.unknowns), 0.0);
  // The iterate's residual first; the Newton matrix (the models' tangents, the most costly part
  // of an evaluation) only for the iterate that is kept, and only when it is needed.
  Trial trial;
  TangentCache tangents;
  auto with_matrix = [&](Trial& t) {
    return t.has_matrix ||
           evaluate(setup, du, gravity, traction, body_step, true, t, result, &tangents);
  };
  if (!evaluate(setup, du, gravity, traction, body_step, false, trial, result)) {
    result.message = "a stress update failed at the start of the increment" + failed_update(trial);
    return false;
  }
  // Predictor: the last increment's nodal displacements scaled to this one's body motion, kept
  // when it lowers the residual (a pile pushed on deforms the soil much as in the last step).
  std::vector<double> predicted = prediction(setup, body_step);
  if (!predicted.empty()) {
    Trial predicted_trial;
    if (evaluate(setup, predicted, gravity, traction, body_step, false, predicted_trial, result) &&
        predicted_trial.residual.norm() < trial.residual.norm()) {
      du.swap(predicted);
      trial = std::move(predicted_trial);
    }
  }
  record.initial_residual = trial.residual.norm();
  record.reference_force = trial.reference_force;
  const double tolerance = settings_.force_tolerance;
  auto force_converged = [&](const Trial& t) {
    return t.residual.norm() <= tolerance * std::max(t.reference_force, 1.0e-300);
  };
  if (setup.unknowns == 0 || force_converged(trial)) {
    record.converged = true;
    commit(setup, du, trial, gravity, traction, body_step);
    return true;
  }

  // The diagnostic line of an iteration (Settings::trace): the largest component of the
  // residual and of the Newton step, with their nodes.
  std::vector<std::pair<int, int>> unknown_node;  // per unknown: node, component
  if (settings_.trace != nullptr) {
    unknown_node.resize(std::size_t(setup.unknowns));
    for (std::size_t c = 0; c < setup.dof.size(); ++c)
      if (setup.dof[c] >= 0) unknown_node[std::size_t(setup.dof[c])] = {int(c / 2), int(c % 2)};
  }
  const auto trace_line = [&](int iteration, const Eigen::VectorXd& step, double length,
                              const IterationRecord& r) {
    const auto where = [&](Eigen::Index d) {
      const auto [node, component] = unknown_node[std::size_t(d)];
      const Vec2 x(grid_.x_axis().node(node % grid_.nx()), grid_.y_axis().node(node / grid_.nx()));
      const std::size_t c = 2 * std::size_t(node) + std::size_t(component);
      return fmt::format("{} at ({:.5g}, {:.5g}) m (int {:.3g}, ext {:.3g}, contact {:.3g} N)",
                         component == 0 ? "x" : "y", x.x(), x.y(), trial.internal[c],
                         trial.external[c], trial.contact[c]);
    };
    Eigen::Index worst = 0;
    std::string text = fmt::format(
        "newton: it {:2d} ||R|| {:.6e} N = {:.3e} F_ref, line {:.4g}, contacts {} slip {} changed "
        "{}, floor {}",
        iteration, r.residual_norm, r.residual_norm / std::max(trial.reference_force, 1e-300),
        length, r.contact_points, r.slipping_points, r.contact_changes, r.floor_particles);
    if (trial.residual.size() > 0) {
      const double largest = trial.residual.cwiseAbs().maxCoeff(&worst);
      text += fmt::format("; largest R {:.3g} N {}", largest, where(worst));
    }
    if (step.size() > 0) {
      const double largest = step.cwiseAbs().maxCoeff(&worst);
      text += fmt::format("; largest step {:.3g} cells {}", largest / grid_.min_spacing(),
                          where(worst));
    }
    std::fprintf(settings_.trace, "%s\n", text.c_str());
  };

  if (settings_.trace != nullptr) {
    IterationRecord start = contact_record(trial.corner, nullptr);
    start.residual_norm = trial.residual.norm();
    start.floor_particles = trial.floor_particles;
    std::fprintf(settings_.trace,
                 "newton: step %ld, sub-increment %.6g of what remains of it, %d unknowns\n",
                 steps_ + 1, fraction, setup.unknowns);
    trace_line(0, Eigen::VectorXd(), 0.0, start);
  }
  // Newton's iterations from (du, trial) until the force balance converges (true; accepted above
  // the force tolerance is counted in the records) or they fail (false, result.message says
  // why). Nothing is committed.
  const auto newton = [&]() -> bool {
    const int max_iterations = settings_.max_iterations;
    SparseMatrix matrix = setup.pattern;
    double first_energy = 0.0;
    // The lowest ||R|| of the iterations so far and the iteration that reached it (stall rule).
    double lowest = std::numeric_limits<double>::infinity();
    int lowest_at = 0;
    for (int iteration = 1; iteration <= max_iterations; ++iteration) {
      ++result.iterations;
      if (!with_matrix(trial)) {
        result.message =
            fmt::format("a stress update failed in iteration {}", iteration) + failed_update(trial);
        return false;
      }
      const auto factor_start = std::chrono::steady_clock::now();
      trial.fill(matrix);
      if (!linear_solver_.factorize(matrix, iteration == 1)) {
        result.seconds_factorisation += seconds_since(factor_start);
        result.message = "the Newton matrix is singular";
        last_matrix_ = matrix;
        return false;
      }
      Eigen::VectorXd step = linear_solver_.solve(-trial.residual);
      // A Newton step that moves a node by more than step_limit cells is scaled down to that:
      // where perfectly plastic soil offers a mechanism, only the contact restrains it, and an
      // iterate that has lifted the soil off a body gives a step along the mechanism of many cells.
      if (settings_.step_limit > 0.0 && step.size() > 0) {
        const double largest = step.cwiseAbs().maxCoeff();
        const double limit = settings_.step_limit * grid_.min_spacing();
        if (largest > limit) step *= limit / largest;
      }
      result.seconds_factorisation += seconds_since(factor_start);
      if (!step.allFinite()) {
        result.message = "the Newton step is not finite";
        return false;
      }
      if (iteration == 1) last_matrix_ = matrix;
      if (settings_.trace != nullptr && settings_.trace_tangent)
        trace_tangent_along(setup, du, step, gravity, traction, body_step, trial, matrix);
      // Line search: halve the step while the residual norm does not fall. If no length lowers it,
      // the length with the smallest residual is taken (not the shortest: near a change of the
      // contact or plastic state the shortest step can raise ||R|| by orders of magnitude).
      const double before = trial.residual.norm();
      const double energy_before = std::abs(step.dot(trial.residual));
      double length = 1.0;
      Trial next, best;
      std::vector<double> best_du;
      double best_norm = std::numeric_limits<double>::infinity(), best_length = 1.0;
      for (int attempt = 0; attempt <= settings_.line_search_steps; ++attempt) {
        std::vector<double> candidate = du;
        for (int d = 0; d < setup.unknowns; ++d) candidate[std::size_t(d)] += length * step[d];
        if (evaluate(setup, candidate, gravity, traction, body_step, false, next, result)) {
          const double norm = next.residual.norm();
          if (norm < best_norm) {
            best_norm = norm;
            best_length = length;
            best_du.swap(candidate);
            std::swap(best, next);
          }
          if (norm < before) break;
        }
        length *= 0.5;
      }
      if (!std::isfinite(best_norm)) {
        result.message =
            fmt::format("a stress update failed in iteration {}'s line search", iteration) +
            failed_update(next);
        return false;
      }
      du.swap(best_du);
      next = std::move(best);
      length = best_length;
      IterationRecord iteration_record = contact_record(next.corner, &trial.corner);
      trial = std::move(next);
      iteration_record.floor_particles = trial.floor_particles;
      iteration_record.residual_norm = trial.residual.norm();
      iteration_record.energy_norm = std::abs(length * step.dot(trial.residual));
      iteration_record.line_search = length;
      if (iteration == 1) first_energy = energy_before;
      record.iterations.push_back(iteration_record);
      if (settings_.trace != nullptr) trace_line(iteration, step, length, iteration_record);
      const bool energy_converged = iteration_record.energy_norm <=
                                    settings_.energy_tolerance * std::max(first_energy, 1e-300);
      if (force_converged(trial) && energy_converged) return true;
      if (iteration_record.residual_norm > 1.0e8 * std::max(record.initial_residual, 1e-300)) {
        result.message = "the Newton iterations diverge";
        return false;
      }
      if (iteration_record.residual_norm < lowest) {
        lowest = iteration_record.residual_norm;
        lowest_at = iteration;
      }
      const int stall = settings_.stall_iterations;
      if (stall > 0 && iteration >= std::max(settings_.accept_after, stall + 1) &&
          iteration - lowest_at >= stall &&
          iteration_record.residual_norm >
              std::max(settings_.accept_tolerance, settings_.force_tolerance) *
                  std::max(trial.reference_force, 1.0e-300)) {
        result.message = fmt::format(
            "no convergence: ||R|| = {:.2g} F_ref, no new lowest residual in the last {} of {} "
            "iterations",
            iteration_record.residual_norm / std::max(trial.reference_force, 1.0e-300), stall,
            iteration);
        return false;
      }
      if (settings_.accept_after > 0 && iteration >= settings_.accept_after &&
          iteration < max_iterations &&
          trial.residual.norm() <=
              settings_.accept_tolerance * std::max(trial.reference_force, 1.0e-300))
        break;
    }
    const double ratio = trial.residual.norm() / std::max(trial.reference_force, 1.0e-300);
    if (ratio <= settings_.accept_tolerance) return true;  // counted where it is committed
    result.message = fmt::format("no convergence in {} iterations (||R|| = {:.2g} F_ref)",
                                 max_iterations, ratio);
    return false;
  };
  // A solution that moves a node by more than 5 cells (or the body's motion, if larger) in one
  // sub-increment is not taken: nodes that only sand without stiffness supports can settle
  // anywhere within the acceptance tolerance (MPM-2 had a particle thrown 67 km so); the
  // sub-increment is cut instead.
  const double drift_limit = std::max(largest_motion(body_step).norm(), 5.0 * grid_.min_spacing());
  const auto drifted = [&](const std::vector<double>& from, const std::vector<double>& to) {
    for (std::size_t d = 0; d < to.size(); ++d)
      if (std::abs(to[d] - (from.empty() ? 0.0 : from[d])) > drift_limit) return true;
    return false;
  };
  // A solution that turns a particle inside out (the volume ratio of its increment, det(I + G)
  // (1 + Δε_θθ) in axisymmetry, not positive) is not taken either, though its residual may be
  // in balance: the stress update integrates the strain and knows nothing of the inversion
  // (MPM-2 with the low-stress stabilisation committed a particle of negative volume so).
  const auto inverted = [&](const Trial& t) -> std::string {
    for (std::size_t i = 0; i < t.gradient.size(); ++i) {
      const double ratio = (Mat2::Identity() + t.gradient[i]).determinant() * (1.0 + t.hoop[i]);
      if (!(ratio > 0.0))
        return fmt::format(
            "particle {} at ({:.5g}, {:.5g}) m would be turned inside out (volume "
            "ratio {:.3g} in the sub-increment)",
            i, particles_.position[i].x(), particles_.position[i].y(), ratio);
    }
    return {};
  };
  if (!newton()) return false;
  if (drifted({}, du)) {
    result.message =
        fmt::format("a node moved more than {:.3g} m in the sub-increment", drift_limit);
    return false;
  }
  if (std::string why = inverted(trial); !why.empty()) {
    result.message = std::move(why);
    return false;
  }
  record.converged = true;
  if (stabilisation_on()) {
    // The low-stress stabilisation only finds the way: the sub-increment is solved again with
    // less of it and without it, and the stabilised solution is kept only where those fail.
    bool exact = false;
    record.stabilisation_share = 1.0;
    if (settings_.low_stress_resolve) {
      // First without the stabilisation, from its solution; where that fails, from the same
      // solution with less of it in stages (Settings::low_stress_continuation), each solve
      // starting from the last one's solution, and from the last stage without it again. The
      // solution of the smallest share that converged is kept.
      std::vector<double> kept_du = du;
      Trial kept_trial = trial;
      // One solve at `scale` from (du, trial); on success its solution is kept, else (du, trial)
      // go back to the last kept solution.
      const auto stage = [&](double scale) {
        stabilisation_scale_ = scale;
        if (settings_.trace != nullptr)
          std::fprintf(settings_.trace, "newton: again with %.3g of the low-stress stabilisation\n",
                       scale);
        bool ok = evaluate(setup, du, gravity, traction, body_step, false, trial, result);
        if (ok && !force_converged(trial)) ok = newton();
        // The drift limit and the inversion check hold for its solution as for the first one's,
        // and it must also stay within the drift limit of the solution it started from. Nodes
        // that only stress-free sand supports do move by cells in such solves without changing
        // the forces: with a limit of the body's motion the quick case kept 107 stabilised
        // solutions instead of 4 and its capacity fell by a quarter, with one cell 14, and its
        // head force scattered by 12 % instead of 6 % (docs/quasi-static.md).
        if (ok && (drifted(kept_du, du) || drifted({}, du) || !inverted(trial).empty())) ok = false;
        if (ok) {
          kept_du = du;
          kept_trial = trial;
          record.stabilisation_share = scale;
        } else {
          du = kept_du;
          trial = kept_trial;
        }
        return ok;
      };
      exact = stage(0.0);
      if (!exact) {
        bool all = true;
        for (const double scale : settings_.low_stress_continuation)
          if (!(all = stage(scale))) break;
        if (all && !settings_.low_stress_continuation.empty()) exact = stage(0.0);
      }
      stabilisation_scale_ = 1.0;
      du = kept_du;
      trial = std::move(kept_trial);
      if (!exact) result.message.clear();
    }
    if (!exact) {
      ++result.stabilised;
      result.largest_stabilisation_share =
          std::max(result.largest_stabilisation_share, record.stabilisation_share);
    }
  }
  // Accepted above the force tolerance (accept_tolerance); at or below it only the energy norm
  // had not converged, and the sub-increment is not counted as accepted (its force balance is).
  const double ratio = trial.residual.norm() / std::max(trial.reference_force, 1.0e-300);
  record.accepted = ratio > settings_.force_tolerance;
  if (record.accepted) {
    ++result.accepted;
    result.largest_accepted_residual = std::max(result.largest_accepted_residual, ratio);
  }
  commit(setup, du, trial, gravity, traction, body_step);
  return true;
}

void QuasiStaticSolver::commit(const StepSetup& setup, const std::vector<double>& du,
                               const Trial& trial, double gravity, double traction,
                               const std::vector<Vec2>& body_step) {
  (void)du;
  Particles& p = particles_;
  const std::size_t count = p.size();
  const bool stretch_domains = settings_.shape_function == ShapeFunction::cpgimp;
  // Work over the step (trapezoidal in the stress and the load factor).
  const double gravity_mean = 0.5 * (gravity + gravity_multiplier_) * settings_.gravity;
  const double traction_mean = 0.5 * (traction + traction_multiplier_);
  // The low-stress stabilisation's reference: this sub-increment's strains, if a body moved.
  if (settings_.low_stress_stiffness > 0.0) {
    const Vec2 motion = largest_motion(body_step);
    if (motion.squaredNorm() > 0.0) {
      reference_strain_ = trial.strain_increment;
      reference_motion_ = motion;
    }
  }
  for (std::size_t i = 0; i < count; ++i) {
    const ParticleNodes& pn = setup.nodes[i];
    Vec2 displacement = Vec2::Zero();
    for (int k = 0; k < pn.count; ++k)
      displacement += pn.weight[k] * trial.node_displacement[std::size_t(pn.node[k])];
    energies_.internal +=
        0.5 * p.volume[i] *
        (p.state[i].stress + trial.state[i].stress).dot(trial.strain_increment[i]);
    // The low-stress stabilisation's stress grows with the strain over the sub-increment and is
    // released after it: its work is dissipated.
    if (!trial.stabilising_stress.empty())
      energies_.damping +=
          0.5 * p.volume[i] * trial.stabilising_stress[i].dot(trial.strain_increment[i]);
    energies_.external_work +=
        (traction_mean * p.external_force[i] - Vec2(0.0, p.mass[i] * gravity_mean))
            .dot(displacement);
    for (int q = 0; q < kCorners; ++q) {
      Vec2& corner = corner_position_[i * kCorners + std::size_t(q)];
      corner += displacement + trial.gradient[i] * (corner - p.position[i]);
    }
    p.position[i] += displacement;
    p.state[i] = trial.state[i];
    Mat2& deformation = p.deformation_gradient[i];
    deformation = (Mat2::Identity() + trial.gradient[i]) * deformation;
    p.out_of_plane_stretch[i] *= 1.0 + trial.hoop[i];
    if (settings_.floor_volume_ratio > 0.0 && trial.fixed_stress[i] != kNotFixed)
      limit_volume_ratio(deformation, p.out_of_plane_stretch[i], settings_.floor_volume_ratio,
                         settings_.geometry == Geometry::axisymmetric);
    p.volume[i] = deformation.determinant() * p.out_of_plane_stretch[i] * p.initial_volume[i];
    // cpGIMP: the domain follows the stretch, as in the explicit solver.
    if (stretch_domains) p.half_size[i] = stretched_half_size(p.initial_half_size[i], deformation);
    if (!grid_.contains(p.position[i].x(), p.position[i].y()) ||
        (settings_.geometry == Geometry::axisymmetric && !(p.position[i].x() > 0.0)))
      throw Error(fmt::format("quasi-static: particle {} left the grid at ({}, {})", i,
                              p.position[i].x(), p.position[i].y()));
  }
  // Contact: forces on the bodies, histories, the largest penetration.
  std::vector<BodyForce> forces = body_forces_;
  for (BodyForce& f : forces) {
    f.total.setZero();
    for (Vec2& part : f.parts) part.setZero();
  }
  max_penetration_ = 0.0;
  for (std::size_t c = 0; c < trial.corner.size(); ++c) {
    const PointContact& point = trial.corner[c];
    ContactHistory& history = contact_history_[c];
    if (!point.active) {
      history = ContactHistory{};
      continue;
    }
    const int body = trial.corner_body[c];
    BodyForce& f = forces[std::size_t(body)];
    f.total -= point.force;
    f.parts[std::size_t(trial.corner_part[c])] -= point.force;
    // Points on the axis (no area in axisymmetry) carry no force; they do not count.
    if (point.normal_force > 0.0)
      max_penetration_ = std::max(max_penetration_, -trial.corner_gap[c]);
    history.body = body;
    history.tangential_force = point.tangential_vector;
  }
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    energies_.contact_work += 0.5 * (body_forces_[b].total + forces[b].total).dot(-body_step[b]);
    bodies_[b].translate(body_step[b]);
  }
  // The contact points back near their particles, with the bodies where they now are.
  bound_corners();
  body_forces_ = std::move(forces);
  // The reaction of the constraints on the soil: the residual f_int - f_ext - f_contact at the
  // constrained components (what the constraint has to add for equilibrium there).
  boundary_reaction_.setZero();
  for (std::size_t c = 0; c < trial.internal.size(); ++c)
    if (setup.active[c / 2] && setup.dof[c] < 0)
      boundary_reaction_[int(c % 2)] += trial.internal[c] - trial.external[c] - trial.contact[c];
  node_displacement_ = trial.node_displacement;
  last_body_step_ = largest_motion(body_step).norm();
  gravity_multiplier_ = gravity;
  traction_multiplier_ = traction;
}

LoadStepResult QuasiStaticSolver::solve_step(const LoadStep& load) {
  LoadStepResult result;
  if (!load.body_displacement.empty() && load.body_displacement.size() != bodies_.size())
    throw InvalidValue("load step body displacements",
                       std::to_string(load.body_displacement.size()),
                       fmt::format("0 or {} (one per rigid body)", bodies_.size()));
  // The contact points within their particles' domains: no change where the last step's commit
  // bounded them; a state restored from a checkpoint written before the bound gets them bounded
  // here (not in restore_run_state, which runs before the particles are restored).
  bound_corners();
  // The state at the start of the step, restored if the step fails.
  const Particles start_particles = particles_;
  const std::vector<RigidBody> start_bodies = bodies_;
  const std::vector<BodyForce> start_forces = body_forces_;
  const std::vector<ContactHistory> start_history = contact_history_;
  const std::vector<Vec2> start_corners = corner_position_;
  const std::vector<Vec2> start_node_displacement = node_displacement_;
  const double start_body_step = last_body_step_;
  const double start_gravity = gravity_multiplier_, start_traction = traction_multiplier_;
  const Energies start_energies = energies_;
  const Vec2 start_reaction = boundary_reaction_;
  const std::vector<Vec6> start_reference_strain = reference_strain_;
  const Vec2 start_reference_motion = reference_motion_;
  const double start_penetration = max_penetration_;
  if (std::all_of(contact_modulus_.begin(), contact_modulus_.end(),
                  [](double m) { return m == 0.0; }))
    contact_modulus_ = penalty_moduli(particles_, materials_);

  double done = 0.0, size = 1.0;
  // The size of the step's first failed sub-increment, where a rescue with the stabilisation
  // starts (StabilisationUse::last_resort); the cuts allowed before it ran out.
  double first_failed = 0.0;
  int cuts_allowed = settings_.max_cuts;
  rescuing_ = false;
  // Whatever way the step ends (an exception from a commit too), the stabilisation is off
  // after it and at its full share.
  struct StabilisationReset {
    QuasiStaticSolver& solver;
    ~StabilisationReset() {
      solver.rescuing_ = false;
      solver.stabilisation_scale_ = 1.0;
    }
  } reset{*this};
  LoadStep remaining = load;
  while (done < 1.0 - 1.0e-12) {
    size = std::min(size, 1.0 - done);
    // The sub-increment as a fraction of what remains of the step.
    const double share = size / (1.0 - done);
    SubIncrementRecord record;
    record.fraction = size;
    LoadStep part = remaining;
    const bool converged = solve_sub_increment(share, part, record, result);
    result.sub_increments.push_back(record);
    if (converged) {
      for (Vec2& d : remaining.body_displacement) d *= 1.0 - share;
      done += size;
      if (int(record.iterations.size()) <= settings_.easy_iterations) size *= 2.0;
      continue;
    }
    if (first_failed == 0.0) first_failed = size;
    if (result.cuts >= cuts_allowed && !rescuing_ && settings_.low_stress_stiffness > 0.0 &&
        settings_.low_stress_use == StabilisationUse::last_resort) {
      // The cuts without the stabilisation ran out: the rest of the step with it, from the size
      // that first failed, with the cuts allowed once more.
      rescuing_ = true;
      result.rescued = true;
      cuts_allowed = result.cuts + settings_.max_cuts;
      size = first_failed;
      if (settings_.trace != nullptr)
        std::fprintf(settings_.trace,
                     "newton: the cuts ran out; the rest of the step with the low-stress "
                     "stabilisation (%s)\n",
                     result.message.c_str());
      continue;
    }
    if (result.cuts >= cuts_allowed) {
      particles_ = start_particles;
      bodies_ = start_bodies;
      body_forces_ = start_forces;
      contact_history_ = start_history;
      corner_position_ = start_corners;
      node_displacement_ = start_node_displacement;
      last_body_step_ = start_body_step;
      gravity_multiplier_ = start_gravity;
      traction_multiplier_ = start_traction;
      energies_ = start_energies;
      boundary_reaction_ = start_reaction;
      reference_strain_ = start_reference_strain;
      reference_motion_ = start_reference_motion;
      max_penetration_ = start_penetration;
      result.converged = false;
      result.message = fmt::format(
          "no convergence after {} cuts{} ({} done of the step): {}", result.cuts,
          result.rescued ? fmt::format(" ({} of them with the low-stress stabilisation)",
                                       result.cuts - settings_.max_cuts)
                         : std::string(),
          format_value(done), result.message);
      return result;
    }
    ++result.cuts;
    size *= 0.5;
  }
  result.converged = true;
  result.message.clear();
  time_ += load.duration;
  ++steps_;
  return result;
}

}  // namespace pilempm::mpm::quasi_static
