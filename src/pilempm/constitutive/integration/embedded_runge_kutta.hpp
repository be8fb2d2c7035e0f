#pragma once
// An explicit embedded Runge-Kutta integrator with adaptive sub-stepping and local error control
// for the rate equations of a constitutive model (in the spirit of Fellin & Ostermann 2002),
// written once for every model: the model supplies the rates and the edges of its domain, the
// integrator the sub-stepping. The same split as MFront's Runge-Kutta integrators and the
// soilmodels UMATs, where the rate function is one routine and the integrator another.
//
// The strain increment is integrated over a pseudo-time t in [0, 1]. What the model supplies (a
// `Problem`, see below) and what the integrator does with it:
//  * Admissibility. A stage point outside the model's domain (Problem::admissible false) that
//    Problem::to_domain can bring back by a projection (for sand: a tensile principal stress
//    while the mean stress is above the floor, cut off to the floor's value) is taken so; any
//    other trial sub-step that leaves the domain is rejected and the sub-step shrunk by 4. Once the
//    sub-step is below `min_substep`, the point has reached the edge of the domain:
//    Problem::set_to_edge puts it there (for sand: the stress-free floor -p_min I, counted as a
//    "floor hit" in UpdateResult). If the rest of the increment still leads out of the domain, the
//    point stays on the edge for the rest of the increment while its other variables follow their
//    rates (Problem::advance_on_edge); otherwise integration goes on. A point that starts outside
//    the domain is brought back by Problem::to_domain where it can be, else put on the edge.
//  * Bounds. After every accepted sub-step Problem::restore_bounds puts the variables back into
//    their bounds (for sand: the void ratio band and |delta| <= R), given a `Hint` that the last
//    rate evaluation left (a value the bounds can reuse, e.g. a factor of the stress level).
//  * Error control. The local error of the embedded lower-order solution, measured by
//    Problem::error_norm, is kept below `tolerance` per sub-step; `fixed_substeps` > 0 switches
//    the control off (equal sub-steps, for convergence studies).
//  * Stability. An explicit scheme is stable for a decaying mode y' = -λ y only while h λ stays
//    inside the scheme's stability interval (h λ <= 2 for Heun-Euler, about 2.51 for
//    Bogacki-Shampine). Beyond it the sub-steps overshoot and the bounds clip them; the error
//    estimate need not see this, and the end point then depends on the increment chaotically
//    (for sand with intergranular strain: a relative change of 1e-9 in a 2 % increment moved the
//    stress by 5 %). Problem::stiffness gives λ for the increment; the adaptive sub-steps stay
//    below kStabilityFraction of the interval.
#include <algorithm>
#include <cmath>
#include <concepts>
#include <limits>
#include <string>
#include <string_view>

#include "pilempm/constitutive/constitutive_model.hpp"

namespace pilempm {

/// How the rate equations are integrated over one strain increment.
struct IntegratorSettings {
  enum class Scheme {
    heun_euler,  ///< modified Euler, 2nd order with a 1st-order error estimate (2 evaluations)
    bogacki_shampine,  ///< RK3(2) of Bogacki & Shampine (1989), 3rd order, FSAL (3 evaluations)
  };
  Scheme scheme = Scheme::heun_euler;
  double tolerance = 1.0e-3;     ///< relative local error per sub-step, in (0, 0.1]
  int fixed_substeps = 0;        ///< > 0: no error control, this many equal sub-steps (studies)
  int max_substeps = 200000;     ///< more accepted plus rejected sub-steps is a failure
  double min_substep = 1.0e-6;   ///< smallest sub-step as a fraction of the increment
  double min_mean_stress = 1.0;  ///< p_min [Pa]: the mean stress floor, > 0

  void validate() const;
};

/// Parses "heun-euler" or "bogacki-shampine".
IntegratorSettings::Scheme parse_integrator_scheme(std::string_view text, std::string_view key);
std::string_view to_string(IntegratorSettings::Scheme scheme);

/// What integrate_embedded_runge_kutta needs of a model's rate equations for one increment.
///   Point: the integrated variables (the same type holds their rates), with
///     void assign_step(const Point& y, double h, const Point& k);   // this = y + h k
///     void add(double h, const Point& k);                           // this += h k
///     void assign_scaled_difference(double s, const Point& a, const Point& b);  // s (a - b)
///     void assign_combination(double h, double w1, const Point& k1, double w2, const Point& k2,
///                             double w3, const Point& k3, double w4, const Point& k4);
///                                                 // this = h (w1 k1 + w2 k2 + w3 k3 + w4 k4)
///     bool operator==(const Point&) const;
///   Hint: what a rate evaluation leaves for restore_bounds (an empty struct if nothing).
///   Hint rate(const Point& y, Point& k) const;           // k = dy/dt at y
///   bool admissible(const Point& y) const;               // y inside the model's domain
///   bool to_domain(Point& y) const;  // y, outside, brought back by a projection if it can be
///   double error_norm(const Point& error, const Point& y) const;  // relative size of error
///   void restore_bounds(Point& y, UpdateResult&, const Hint* nearby) const;
///   void set_to_edge(Point& y) const;                    // onto the edge of the domain
///   void advance_on_edge(Point& y, double dt, const Point& k) const;  // other variables move
///   double stiffness() const;  // λ: a bound of the fastest decay rate over the increment, >= 0
template <class Problem>
concept RungeKuttaProblem = requires(const Problem& problem, typename Problem::Point& y,
                                     const typename Problem::Point& c, UpdateResult& result,
                                     const typename Problem::Hint* hint, double h) {
  { problem.rate(c, y) } -> std::same_as<typename Problem::Hint>;
  { problem.admissible(c) } -> std::same_as<bool>;
  { problem.to_domain(y) } -> std::same_as<bool>;
  { problem.error_norm(c, c) } -> std::same_as<double>;
  problem.restore_bounds(y, result, hint);
  problem.set_to_edge(y);
  problem.advance_on_edge(y, h, c);
  { problem.stiffness() } -> std::same_as<double>;
  y.assign_step(c, h, c);
  y.add(h, c);
  y.assign_scaled_difference(h, c, c);
  y.assign_combination(h, h, c, h, c, h, c, h, c);
  { c == c } -> std::same_as<bool>;
};

/// The part of a scheme's stability interval the adaptive sub-steps use (see Stability above).
inline constexpr double kStabilityFraction = 0.8;

namespace detail {

// Whether y lies in the problem's domain, or was brought back into it by Problem::to_domain.
template <RungeKuttaProblem Problem>
bool in_domain(const Problem& problem, typename Problem::Point& y) {
  return problem.admissible(y) || problem.to_domain(y);
}

// The stages of one sub-step of either scheme, shared by the adaptive integration and the replay
// of a recorded path (so that both take a sub-step with the same arithmetic, to the last bit).
template <RungeKuttaProblem Problem>
struct RungeKuttaStages {
  typename Problem::Point k1, k2, k3, k4, trial, low;
  typename Problem::Hint nearby{};  // of the last rate evaluation, close to the end point

  // From y (k1 its rate) over h: the higher-order end point into `trial` (and, for
  // Bogacki-Shampine, its rate into k4). False where a stage leaves the domain. With `error`,
  // the norm of the embedded estimate of the local error.
  bool step(const Problem& problem, const typename Problem::Point& y, double h, bool heun,
            double* error) {
    if (heun) {
      // Modified Euler: y1 = y + h k1 (1st order), y2 = y + h/2 (k1 + k2) (2nd order).
      trial.assign_step(y, h, k1);
      if (!in_domain(problem, trial)) return false;
      nearby = problem.rate(trial, k2);
      trial.assign_step(y, 0.5 * h, k1);
      trial.add(0.5 * h, k2);
      if (!in_domain(problem, trial)) return false;
      if (error) {
        low.assign_scaled_difference(0.5 * h, k2, k1);
        *error = problem.error_norm(low, trial);
      }
      return true;
    }
    // Bogacki & Shampine (1989) RK3(2): c = (0, 1/2, 3/4, 1), FSAL.
    trial.assign_step(y, 0.5 * h, k1);
    if (!in_domain(problem, trial)) return false;
    problem.rate(trial, k2);
    trial.assign_step(y, 0.75 * h, k2);
    if (!in_domain(problem, trial)) return false;
    problem.rate(trial, k3);
    trial.assign_step(y, 2.0 / 9.0 * h, k1);
    trial.add(1.0 / 3.0 * h, k2);
    trial.add(4.0 / 9.0 * h, k3);
    if (!in_domain(problem, trial)) return false;
    nearby = problem.rate(trial, k4);
    if (error) {
      // y3 - y2 with the 2nd-order weights (7/24, 1/4, 1/3, 1/8).
      const double w1 = 2.0 / 9.0 - 7.0 / 24.0, w2 = 1.0 / 3.0 - 0.25, w3 = 4.0 / 9.0 - 1.0 / 3.0,
                   w4 = -0.125;
      low.assign_combination(h, w1, k1, w2, k2, w3, k3, w4, k4);
      *error = problem.error_norm(low, trial);
    }
    return true;
  }
};

}  // namespace detail

/// Integrates the problem's rates from y over t in [0, 1] with the settings' scheme; y becomes
/// the end point. On failure (UpdateResult::ok false) y is left wherever the integration stopped:
/// the caller keeps its own copy of the start. With `record`, the accepted sub-steps go into it
/// (not replayable if the point reached the edge of the domain or the path has more runs than
/// SubstepPath holds).
template <RungeKuttaProblem Problem>
UpdateResult integrate_embedded_runge_kutta(const Problem& problem, typename Problem::Point& y,
                                            const IntegratorSettings& settings,
                                            SubstepPath* record = nullptr) {
  using Point = typename Problem::Point;
  UpdateResult result;
  if (record) {
    record->clear();
    record->replayable = true;
  }
  if (!detail::in_domain(problem, y)) {  // starts outside: onto the edge
    if (record) record->replayable = false;
    problem.set_to_edge(y);
    ++result.mean_stress_floor_hits;
  }
  const bool adaptive = settings.fixed_substeps == 0;
  const bool heun = settings.scheme == IntegratorSettings::Scheme::heun_euler;
  // (tolerance / error)^(1 / (order of the error estimate + 1)), without pow() (it ran once a
  // step for every particle of an MPM run).
  auto step_factor = [heun](double ratio) { return heun ? std::sqrt(ratio) : std::cbrt(ratio); };

  // The largest stable sub-step: the real stability interval of the scheme over λ.
  const double stiffness = problem.stiffness();
  const double stable_step = stiffness > 0.0 ? kStabilityFraction * (heun ? 2.0 : 2.51) / stiffness
                                             : std::numeric_limits<double>::infinity();
  double t = 0.0;
  double h = adaptive ? 1.0 : 1.0 / settings.fixed_substeps;
  detail::RungeKuttaStages<Problem> stages;
  Point &k1 = stages.k1, &trial = stages.trial;
  bool k1_valid = false;
  int attempts = 0;
  while (t < 1.0) {
    if (++attempts > settings.max_substeps) {
      result.ok = false;
      result.message = "Runge-Kutta integrator: too many sub-steps";
      return result;
    }
    h = std::min(h, 1.0 - t);
    if (adaptive) h = std::min(h, stable_step);
    if (!k1_valid) problem.rate(y, k1);
    double error = 0.0;
    const bool inside = stages.step(problem, y, h, heun, adaptive ? &error : nullptr);

    if (!inside) {
      if (h > settings.min_substep) {  // approach the edge of the domain with smaller steps
        h *= 0.25;
        ++result.rejected_substeps;
        k1_valid = true;
        continue;
      }
      // The edge is reached within min_substep: the point goes onto it.
      if (record) record->replayable = false;
      problem.set_to_edge(y);
      ++result.mean_stress_floor_hits;
      t += h;
      problem.restore_bounds(y, result, nullptr);
      k1_valid = false;
      // Does the rest of the increment keep leading out? Then the point stays on the edge.
      problem.rate(y, k1);
      trial.assign_step(y, 1.0 - t, k1);
      if (!detail::in_domain(problem, trial)) {
        problem.advance_on_edge(y, 1.0 - t, k1);
        problem.restore_bounds(y, result, nullptr);
        t = 1.0;
        break;
      }
      k1_valid = true;
      h = 1.0 - t;
      continue;
    }

    if (adaptive && error > settings.tolerance) {
      h *= std::max(0.1, 0.9 * step_factor(settings.tolerance / error));
      ++result.rejected_substeps;
      k1_valid = true;
      if (h < settings.min_substep) {
        result.ok = false;
        result.message = "Runge-Kutta integrator: sub-step below min_substep at the tolerance";
        return result;
      }
      continue;
    }
    // Accept.
    if (record) record->append(h);
    y = trial;
    problem.restore_bounds(y, result, &stages.nearby);
    t += h;
    ++result.substeps;
    // FSAL: k4 is the rate at the accepted point unless the bounds moved it.
    if (!heun && y == trial) {
      k1 = stages.k4;
      k1_valid = true;
    } else {
      k1_valid = false;
    }
    if (adaptive) {
      const double growth = error > 0.0 ? 0.9 * step_factor(settings.tolerance / error) : 4.0;
      h *= std::clamp(growth, 0.2, 4.0);
    }
  }
  return result;
}

/// Integrates the problem's rates from y along the recorded sub-steps of `path` (replayable), with
/// the settings' scheme and the same arithmetic as integrate_embedded_runge_kutta but no error
/// control: for the path an adaptive integration recorded and the same rates, the same end point
/// to the last bit. Fails (ok false, y left where it stopped) where a stage leaves the domain.
template <RungeKuttaProblem Problem>
UpdateResult replay_embedded_runge_kutta(const Problem& problem, typename Problem::Point& y,
                                         const IntegratorSettings& settings,
                                         const SubstepPath& path) {
  UpdateResult result;
  const auto leave = [&result] {
    result.ok = false;
    result.message = "Runge-Kutta integrator: a replayed sub-step leaves the model's domain";
    return result;
  };
  if (!path.replayable || !detail::in_domain(problem, y)) return leave();
  const bool heun = settings.scheme == IntegratorSettings::Scheme::heun_euler;
  detail::RungeKuttaStages<Problem> stages;
  bool k1_valid = false;
  for (int run = 0; run < path.runs; ++run)
    for (int j = 0; j < path.repeat[std::size_t(run)]; ++j) {
      if (!k1_valid) problem.rate(y, stages.k1);
      if (!stages.step(problem, y, path.step[std::size_t(run)], heun, nullptr)) return leave();
      y = stages.trial;
      problem.restore_bounds(y, result, &stages.nearby);
      ++result.substeps;
      k1_valid = !heun && y == stages.trial;  // FSAL, as in the adaptive integration
      if (k1_valid) stages.k1 = stages.k4;
    }
  return result;
}

}  // namespace pilempm
