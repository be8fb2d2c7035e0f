#include "pilempm/element/mixed_control_driver.hpp"

#include <fmt/format.h>

#include "pilempm/core/error.hpp"

namespace pilempm {

MixedControlDriver::MixedControlDriver(const ConstitutiveModel& model, const MaterialState& initial,
                                       MixedControlSettings settings)
    : model_(model), state_(initial), settings_(settings) {}

UpdateResult MixedControlDriver::apply(const MixedIncrement& increment) {
  ++count_;
  std::array<int, 6> unknown{};
  int n = 0;
  for (int i = 0; i < 6; ++i)
    if (increment.stress_controlled[i]) unknown[n++] = i;

  Vec6 d_eps = increment.strain_increment;
  // First guess for the solved components: what the previous increment needed, when it was
  // controlled the same way (smooth loading programmes need few corrections then).
  if (increment.stress_controlled == last_control_)
    for (int r = 0; r < n; ++r) d_eps[unknown[r]] = last_increment_[unknown[r]];
  MaterialState trial = state_;
  UpdateResult result = model_.update(trial, d_eps);
  auto fail_if_bad = [&](const UpdateResult& r) {
    if (!r.ok)
      throw Error(
          fmt::format("element test: the model failed at increment {}: {}", count_, r.message));
  };

  if (n > 0) {
    // Solve stress(d_eps)[unknown] = target[unknown] for d_eps[unknown]: Newton with the model's
    // tangent as the first Jacobian, improved by Broyden's rank-one updates.
    using MatX = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
    using VecX = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;
    const Mat6 tangent = model_.tangent(state_, d_eps);
    MatX J(n, n);
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c) J(r, c) = tangent(unknown[r], unknown[c]);
    auto residual = [&](const MaterialState& s) {
      VecX res(n);
      for (int r = 0; r < n; ++r)
        res[r] = s.stress[unknown[r]] - increment.stress_target[unknown[r]];
      return res;
    };
    const double scale = std::max(increment.stress_target.cwiseAbs().maxCoeff(),
                                  state_.stress.cwiseAbs().maxCoeff());
    const double tolerance = settings_.stress_tolerance + settings_.relative_tolerance * scale;
    const double acceptable =
        settings_.stress_tolerance + settings_.acceptable_relative_tolerance * scale;
    fail_if_bad(result);
    VecX res = residual(trial);
    double best = res.cwiseAbs().maxCoeff();
    int iteration = 0, stalled = 0;
    while (!(res.cwiseAbs().maxCoeff() <= tolerance)) {  // the negation also stops on NaN
      // Where the integrator's sub-step pattern makes the stress jump by more than the target
      // tolerance, accept the acceptable one once the iteration stops improving.
      const bool stalling = stalled >= 4 || iteration >= settings_.max_iterations;
      if (stalling && res.cwiseAbs().maxCoeff() <= acceptable) break;
      if (++iteration > settings_.max_iterations)
        throw Error(fmt::format(
            "element test: stress control did not converge at increment {} (residual {:.3g} Pa "
            "after {} iterations, acceptable {:.3g} Pa)",
            count_, res.cwiseAbs().maxCoeff(), settings_.max_iterations, acceptable));
      VecX step = -J.fullPivLu().solve(res);
      // A correction the model cannot integrate (far outside the range of the tangent) is
      // halved until it can; a model failure on the converged increment is still an error.
      const Vec6 before = d_eps;
      for (int halvings = 0;; ++halvings) {
        for (int r = 0; r < n; ++r) d_eps[unknown[r]] = before[unknown[r]] + step[r];
        trial = state_;
        result = model_.update(trial, d_eps);
        if (result.ok || halvings == 20) break;
        step *= 0.5;
      }
      fail_if_bad(result);
      const VecX new_res = residual(trial);
      const VecX change = new_res - res;
      if (step.squaredNorm() > 0.0)
        J += (change - J * step) * step.transpose() / step.squaredNorm();
      res = new_res;
      const double size = res.cwiseAbs().maxCoeff();
      stalled = size < 0.5 * best ? 0 : stalled + 1;
      best = std::min(best, size);
    }
  }
  fail_if_bad(result);
  state_ = trial;
  strain_ += d_eps;
  last_increment_ = d_eps;
  last_control_ = increment.stress_controlled;
  return result;
}

}  // namespace pilempm
