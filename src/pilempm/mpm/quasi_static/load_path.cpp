#include "pilempm/mpm/quasi_static/load_path.hpp"

#include <cmath>

#include "pilempm/core/error.hpp"

namespace pilempm::mpm::quasi_static {

std::vector<PushPoint> push_body(QuasiStaticSolver& solver, int body, const Vec2& step, int steps,
                                 double gravity_multiplier,
                                 const std::function<void(const LoadStepResult&)>& observer) {
  std::vector<PushPoint> points;
  const Vec2 direction = step.normalized();
  const Vec2 start = solver.rigid_body(body).displacement();
  LoadStep load;
  load.gravity_multiplier = gravity_multiplier;
  load.body_displacement.assign(std::size_t(solver.rigid_body_count()), Vec2::Zero());
  load.body_displacement[std::size_t(body)] = step;
  for (int k = 0; k < steps; ++k) {
    const LoadStepResult r = solver.solve_step(load);
    if (observer) observer(r);
    PushPoint point;
    point.travel = (solver.rigid_body(body).displacement() - start).dot(direction);
    point.force = solver.body_force(body).total;
    point.iterations = r.iterations;
    point.cuts = r.cuts;
    point.penetration = solver.max_penetration();
    point.converged = r.converged;
    point.message = r.message;
    points.push_back(point);
    if (!r.converged) break;
  }
  return points;
}

namespace {

// Coefficients of the least-squares polynomial in t = (x - centre) / half_range.
Eigen::VectorXd fit(const std::vector<double>& x, const std::vector<double>& y, int degree,
                    double& centre, double& half_range) {
  if (x.size() != y.size() || degree < 0 || x.size() < std::size_t(degree) + 2)
    throw InvalidValue("polynomial fit points", std::to_string(x.size()),
                       "as many x as y, and at least degree + 2");
  double lo = x.front(), hi = x.front();
  for (double v : x) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  centre = 0.5 * (lo + hi);
  half_range = hi > lo ? 0.5 * (hi - lo) : 1.0;
  Eigen::MatrixXd a(long(x.size()), degree + 1);
  Eigen::VectorXd b(long(x.size()));
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double t = (x[i] - centre) / half_range;
    double power = 1.0;
    for (int d = 0; d <= degree; ++d, power *= t) a(long(i), d) = power;
    b(long(i)) = y[i];
  }
  return a.colPivHouseholderQr().solve(b);
}

double evaluate(const Eigen::VectorXd& c, double t) {
  double value = 0.0;
  for (long d = c.size() - 1; d >= 0; --d) value = value * t + c(d);
  return value;
}

}  // namespace

double scatter_about_fit(const std::vector<double>& x, const std::vector<double>& y, int degree) {
  double centre = 0.0, half_range = 1.0;
  const Eigen::VectorXd c = fit(x, y, degree, centre, half_range);
  double squares = 0.0, mean = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double r = y[i] - evaluate(c, (x[i] - centre) / half_range);
    squares += r * r;
    mean += y[i];
  }
  const double n = static_cast<double>(x.size());
  return std::sqrt(squares / n) / std::abs(mean / n);
}

double fit_value(const std::vector<double>& x, const std::vector<double>& y, int degree,
                 double at) {
  double centre = 0.0, half_range = 1.0;
  const Eigen::VectorXd c = fit(x, y, degree, centre, half_range);
  return evaluate(c, (at - centre) / half_range);
}

}  // namespace pilempm::mpm::quasi_static
