// The check of the quasi-static solver's Newton matrix against the derivative of its residual
// (QuasiStaticSolver::check_tangent): central differences of the residual along a direction, in
// total and by part, for tests and for finding what slows the Newton iterations down.
#include <algorithm>
#include <cmath>

#include "pilempm/core/error.hpp"
#include "pilempm/mpm/quasi_static/step_data.hpp"

namespace pilempm::mpm::quasi_static {

using namespace detail;

namespace {

// K v for the entries of one part.
template <class Entries>
Eigen::VectorXd product(const Entries& entries, const Eigen::VectorXd& v) {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(v.size());
  for (const auto& e : entries) out[e.row] += e.value * v[e.column];
  return out;
}

// The node-component array `a` at the unknowns.
Eigen::VectorXd at_unknowns(const std::vector<int>& dof, const std::vector<double>& a,
                            int unknowns) {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(unknowns);
  for (std::size_t c = 0; c < dof.size(); ++c)
    if (dof[c] >= 0) out[dof[c]] = a[c];
  return out;
}

double ratio(double a, double b) {
  return b > 0.0 ? a / b : (a > 0.0 ? HUGE_VAL : 0.0);
}

}  // namespace

TangentCheck QuasiStaticSolver::check_tangent(const LoadStep& load, double fraction,
                                              double relative_step) const {
  const Targets target = targets(fraction, load);
  const double gravity = target.gravity, traction = target.traction;
  const std::vector<Vec2>& body_step = target.body_step;
  StepSetup setup;
  build_setup(setup);
  TangentCheck check;
  check.unknowns = setup.unknowns;
  if (setup.unknowns == 0) return check;
  std::vector<double> du = prediction(setup, body_step);
  if (du.empty()) du.assign(std::size_t(setup.unknowns), 0.0);
  LoadStepResult ignored;
  Trial at, plus, minus;
  if (!evaluate(setup, du, gravity, traction, body_step, true, at, ignored))
    throw Error("quasi-static: check_tangent: a stress update failed at the iterate");
  // A fixed pseudo-random direction (a linear congruential sequence), entries in [-1, 1].
  Eigen::VectorXd v(setup.unknowns);
  unsigned long long seed = 12345;
  for (int d = 0; d < setup.unknowns; ++d) {
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    v[d] = double(seed >> 11) / double(1ULL << 53) * 2.0 - 1.0;
  }
  const double h = relative_step * grid_.min_spacing();
  std::vector<double> up = du, down = du;
  for (int d = 0; d < setup.unknowns; ++d) {
    up[std::size_t(d)] += h * v[d];
    down[std::size_t(d)] -= h * v[d];
  }
  if (!evaluate(setup, up, gravity, traction, body_step, false, plus, ignored) ||
      !evaluate(setup, down, gravity, traction, body_step, false, minus, ignored))
    throw Error("quasi-static: check_tangent: a stress update failed near the iterate");
  const Eigen::VectorXd difference = (plus.residual - minus.residual) / (2.0 * h);
  const auto part_difference = [&](const std::vector<double> Trial::*array) {
    return Eigen::VectorXd((at_unknowns(setup.dof, plus.*array, setup.unknowns) -
                            at_unknowns(setup.dof, minus.*array, setup.unknowns)) /
                           (2.0 * h));
  };
  SparseMatrix material = setup.pattern;
  std::copy(at.material_values.begin(), at.material_values.end(), material.valuePtr());
  const Eigen::VectorXd kv_material = material * v;
  const Eigen::VectorXd kv_contact = product(at.contact_entries, v);
  const Eigen::VectorXd ghost = product(at.ghost_entries, v);
  const Eigen::VectorXd kv = kv_material + kv_contact + ghost;
  check.matrix_norm = kv.norm();
  check.total = ratio((kv - difference).norm(), kv.norm());
  // The internal force holds the ghost springs too (linear, their matrix exact).
  check.material = ratio((kv_material + ghost - part_difference(&Trial::internal)).norm(),
                         (kv_material + ghost).norm());
  // R = f_int − f_ext − f_contact: the contact's matrix is −∂f_contact/∂u.
  check.contact = ratio((kv_contact + part_difference(&Trial::contact)).norm(), kv_contact.norm());
  Eigen::Index worst = 0;
  (kv - difference).cwiseAbs().maxCoeff(&worst);
  for (std::size_t c = 0; c < setup.dof.size(); ++c)
    if (setup.dof[c] == int(worst)) {
      const int n = int(c / 2);
      check.worst_node =
          Vec2(grid_.x_axis().node(n % grid_.nx()), grid_.y_axis().node(n / grid_.nx()));
      check.worst_component = int(c % 2);
    }
  return check;
}

}  // namespace pilempm::mpm::quasi_static
