#pragma once
// A rigid body pushed through the soil in equal displacement load steps, and the smoothness of
// the force it meets (docs/verification.md §9): the verifications of the quasi-static analysis
// and its benchmark program share these.
#include <functional>
#include <string>
#include <vector>

#include "pilempm/mpm/quasi_static/quasi_static_solver.hpp"

namespace pilempm::mpm::quasi_static {

/// The state after one load step of a push.
struct PushPoint {
  double travel = 0.0;        ///< the body's displacement along the push so far [m]
  Vec2 force = Vec2::Zero();  ///< contact force on the body (BodyForce::total) [N]
  int iterations = 0;         ///< Newton iterations of the step (failed sub-increments too)
  int cuts = 0;
  double penetration = 0.0;  ///< largest penetration of a contact point [m]
  bool converged = true;
  std::string message;  ///< why the step failed
};

/// Pushes body `body` by `step` per load step, `steps` times, the gravity multiplier held at
/// `gravity_multiplier`; one point per step. Stops after the first step that does not converge
/// (its point has converged = false and the state of its start). `observer`, if given, sees
/// each step's result.
std::vector<PushPoint> push_body(QuasiStaticSolver& solver, int body, const Vec2& step, int steps,
                                 double gravity_multiplier,
                                 const std::function<void(const LoadStepResult&)>& observer = {});

/// The root-mean-square deviation of y about its least-squares polynomial fit of `degree` in x,
/// over the mean of y: the scatter of a force along a path about its smooth trend. Throws
/// InvalidValue for fewer than degree + 2 points or sizes that differ.
double scatter_about_fit(const std::vector<double>& x, const std::vector<double>& y, int degree);

/// The least-squares polynomial fit of `degree` in x, evaluated at `at`.
double fit_value(const std::vector<double>& x, const std::vector<double>& y, int degree, double at);

}  // namespace pilempm::mpm::quasi_static
