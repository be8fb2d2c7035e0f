// The check of the quasi-static solver's Newton matrix against the derivative of its residual
// (QuasiStaticSolver::check_tangent): central differences of the residual along a direction, in
// total and by part, for tests and for finding what slows the Newton iterations down.
#include <algorithm>
#include <cmath>
#include <cstdio>

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

void QuasiStaticSolver::trace_tangent_along(const StepSetup& setup, const std::vector<double>& du,
                                            const Eigen::VectorXd& step, double gravity,
                                            double traction, const std::vector<Vec2>& body_step,
                                            const Trial& at, const SparseMatrix& matrix) const {
  std::FILE* trace = settings_.trace;
  const double scale = 1.0e-4;  // of the Newton step, for the central differences
  LoadStepResult ignored;
  Trial plus, minus, full;
  std::vector<double> up = du, down = du, ahead = du;
  for (int d = 0; d < setup.unknowns; ++d) {
    up[std::size_t(d)] += scale * step[d];
    down[std::size_t(d)] -= scale * step[d];
    ahead[std::size_t(d)] += step[d];
  }
  if (!evaluate(setup, up, gravity, traction, body_step, false, plus, ignored) ||
      !evaluate(setup, down, gravity, traction, body_step, false, minus, ignored) ||
      !evaluate(setup, ahead, gravity, traction, body_step, false, full, ignored)) {
    std::fprintf(trace, "tangent: a stress update failed along the step\n");
    return;
  }
  const auto internal = [&](const Trial& t) {
    return at_unknowns(setup.dof, t.internal, setup.unknowns);
  };
  const auto contact = [&](const Trial& t) {
    return Eigen::VectorXd(-at_unknowns(setup.dof, t.contact, setup.unknowns));
  };
  // K s by part (the ghost springs are in the internal force) and the residual's central
  // difference along s.
  SparseMatrix material = setup.pattern;
  std::copy(at.material_values.begin(), at.material_values.end(), material.valuePtr());
  const Eigen::VectorXd km = material * step + product(at.ghost_entries, step);
  const Eigen::VectorXd kc = product(at.contact_entries, step);
  const Eigen::VectorXd ks = matrix * step;
  const Eigen::VectorXd difference = (plus.residual - minus.residual) / (2.0 * scale);
  const Eigen::VectorXd dm = (internal(plus) - internal(minus)) / (2.0 * scale);
  const Eigen::VectorXd dc = (contact(plus) - contact(minus)) / (2.0 * scale);
  std::fprintf(trace,
               "tangent: along the step: |dR/ds - Ks| / |Ks| %.3g (material %.3g, contact %.3g); "
               "over the whole step: |R(du + s)| / |R| %.3g, what K s misses: material %.4g N, "
               "contact %.4g N\n",
               ratio((difference - ks).norm(), ks.norm()), ratio((dm - km).norm(), ks.norm()),
               ratio((dc - kc).norm(), ks.norm()), ratio(full.residual.norm(), at.residual.norm()),
               (internal(full) - internal(at) - km).norm(),
               (contact(full) - contact(at) - kc).norm());
  // The particles whose stress change between two evaluations (from `a` to `b`, their iterates
  // apart by `apart` times the Newton step) differs most from the prediction of the tangents at
  // the iterate: |Δσ − D Δε − d_w Δw| V / apart, largest first.
  const auto worst_particles = [&](const char* what, const Trial& a, const Trial& b, double apart) {
    const Particles& particles = particles_;
    struct Entry {
      double error;
      std::size_t particle;
    };
    std::vector<Entry> entries;
    double total = 0.0;
    for (std::size_t k = 0; k < particles.size(); ++k) {
      const Vec6 ds = (b.state[k].stress - a.state[k].stress) / apart;
      const Vec6 de = (b.strain_increment[k] - a.strain_increment[k]) / apart;
      const double dw = 0.5 *
                        ((b.gradient[k](1, 0) - b.gradient[k](0, 1)) -
                         (a.gradient[k](1, 0) - a.gradient[k](0, 1))) /
                        apart;
      Vec4 e4, s4;
      for (int r = 0; r < 4; ++r) {
        e4[r] = de[kComponents[r]];
        s4[r] = ds[kComponents[r]];
      }
      const double error =
          (s4 - at.tangent[k] * e4 - at.spin_tangent[k] * dw).norm() * particles.volume[k];
      total += error * error;
      entries.push_back({error, k});
    }
    const std::size_t shown = std::min<std::size_t>(4, entries.size());
    std::partial_sort(entries.begin(), entries.begin() + long(shown), entries.end(),
                      [](const Entry& x, const Entry& y) { return x.error > y.error; });
    std::fprintf(trace, "tangent: %s: particles' |dsigma - D de| V, all %.3g N m; largest:\n", what,
                 std::sqrt(total));
    for (std::size_t w = 0; w < shown; ++w) {
      const std::size_t k = entries[w].particle;
      const Vec6& s = at.state[k].stress;
      std::fprintf(trace,
                   "tangent:   particle %zu at (%.5g, %.5g) m: %.3g N m; p %.4g kPa, |strain "
                   "increment| %.3g, floor %d\n",
                   k, particles.position[k].x(), particles.position[k].y(), entries[w].error,
                   -(s[k11] + s[k22] + s[k33]) / 3.0e3, at.strain_increment[k].norm(),
                   int(at.fixed_stress[k]));
    }
  };
  worst_particles("along the step", minus, plus, 2.0 * scale);
  worst_particles("over the whole step", at, full, 1.0);
}

}  // namespace pilempm::mpm::quasi_static
