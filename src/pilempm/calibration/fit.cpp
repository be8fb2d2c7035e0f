#include "pilempm/calibration/fit.hpp"

#include <ceres/ceres.h>
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <nlopt.hpp>

#include "pilempm/core/error.hpp"

namespace pilempm::calibration {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double sum_of_squares(const std::vector<double>& r) {
  double s = 0.0;
  for (double x : r) s += x * x;
  return s;
}

// A parameter set the model accepts (throws nothing): validate() and the f_b condition.
bool admissible(const ParameterSet& s) {
  try {
    s.hypoplastic.validate();
    if (s.igs.enabled()) s.igs.validate();
  } catch (const InvalidValue&) {
    return false;
  }
  return true;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Evaluator

Evaluator::Evaluator(const CalibrationProblem& problem) : problem_(problem) {
  for (const LabTest& t : problem.tests) residual_count_ += calibration::residual_count(t);
}

std::vector<std::optional<std::vector<double>>> Evaluator::run_sets(
    const std::vector<ParameterSet>& sets, const std::vector<std::size_t>& tests) {
  const std::size_t n_sets = sets.size(), n_tests = tests.size();
  std::vector<ModelPtr> models(n_sets);
  for (std::size_t i = 0; i < n_sets; ++i)
    if (admissible(sets[i])) models[i] = make_hypoplastic(sets[i], problem_.integrator);
  // One task per (set, test); the slowest tests (triaxial) first would balance better, but the
  // dynamic schedule over many tasks is close enough.
  std::vector<std::optional<std::vector<double>>> parts(n_sets * n_tests);
  const long tasks = static_cast<long>(n_sets * n_tests);
#pragma omp parallel for schedule(dynamic) num_threads(std::max(1, problem_.threads))
  for (long task = 0; task < tasks; ++task) {
    const std::size_t i = static_cast<std::size_t>(task) / n_tests;
    const std::size_t k = static_cast<std::size_t>(task) % n_tests;
    if (!models[i]) continue;
    const LabTest& test = problem_.tests[tests[k]];
    const auto simulated = simulate(test, models[i]);
    ++runs_;
    if (simulated) parts[static_cast<std::size_t>(task)] = test_residuals(test, *simulated);
  }
  std::vector<std::optional<std::vector<double>>> result(n_sets);
  for (std::size_t i = 0; i < n_sets; ++i) {
    std::vector<double> r;
    bool ok = static_cast<bool>(models[i]);
    for (std::size_t k = 0; k < n_tests && ok; ++k) {
      const auto& part = parts[i * n_tests + k];
      if (!part) {
        ok = false;
        break;
      }
      r.insert(r.end(), part->begin(), part->end());
    }
    if (ok) result[i] = std::move(r);
  }
  return result;
}

std::optional<std::vector<double>> Evaluator::residuals(const ParameterSet& s,
                                                        const std::vector<std::size_t>& tests) {
  std::vector<std::size_t> which = tests;
  if (which.empty())
    for (std::size_t k = 0; k < problem_.tests.size(); ++k) which.push_back(k);
  return run_sets({s}, which).front();
}

std::optional<std::vector<double>> Evaluator::residuals(const std::vector<double>& u) {
  return residuals(parameters_at(problem_, u));
}

bool Evaluator::jacobian(const std::vector<double>& u, const std::vector<double>& r0,
                         Eigen::MatrixXd& J) {
  const std::size_t p = u.size();
  std::vector<ParameterSet> sets;
  std::vector<double> steps;
  for (std::size_t j = 0; j < p; ++j) {
    std::vector<double> v = u;
    const double h = u[j] + kStep <= 1.0 ? kStep : -kStep;  // stay inside the bounds
    v[j] += h;
    steps.push_back(h);
    sets.push_back(parameters_at(problem_, v));
  }
  std::vector<std::size_t> all;
  for (std::size_t k = 0; k < problem_.tests.size(); ++k) all.push_back(k);
  const auto columns = run_sets(sets, all);
  J.resize(static_cast<Eigen::Index>(r0.size()), static_cast<Eigen::Index>(p));
  for (std::size_t j = 0; j < p; ++j) {
    if (!columns[j]) return false;
    for (std::size_t i = 0; i < r0.size(); ++i)
      J(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
          ((*columns[j])[i] - r0[i]) / steps[j];
  }
  return true;
}

// ---------------------------------------------------------------------------------------------
// Stage 2: refinement

namespace {

// Bookkeeping shared by both optimisers: history, progress, the last evaluation.
struct RefineContext {
  Evaluator& evaluator;
  const FitObserver& observer;
  Clock::time_point start;
  std::vector<HistoryRow>& history;
  int max_steps = 0;
  double best_misfit = std::numeric_limits<double>::infinity();
  std::vector<double> best_u;

  void record(int step, const std::vector<double>& u, double misfit) {
    const CalibrationProblem& problem = evaluator.problem();
    history.push_back({"refine", step, evaluator.runs(), seconds_since(start), misfit,
                       parameters_at(problem, u)});
    if (misfit < best_misfit) {
      best_misfit = misfit;
      best_u = u;
    }
    if (observer) {
      FitProgress p;
      p.stage = "refine";
      p.step = step;
      p.max_steps = max_steps;
      p.runs = evaluator.runs();
      p.seconds = seconds_since(start);
      p.misfit = misfit;
      p.seconds_left = step > 0 ? p.seconds / step * std::max(0, max_steps - step) : 0.0;
      observer(p);
    }
  }
};

// The misfit of all tests as one Ceres residual block; the Jacobian by forward differences in
// parallel (Evaluator::jacobian). The last residuals are cached: Ceres asks for the Jacobian at
// a point whose residuals it has just computed.
class MisfitCost final : public ceres::CostFunction {
 public:
  MisfitCost(Evaluator& evaluator, std::size_t parameters) : evaluator_(evaluator) {
    set_num_residuals(static_cast<int>(evaluator.residual_count()));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(parameters));
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const std::size_t p = static_cast<std::size_t>(parameter_block_sizes()[0]);
    std::vector<double> u(parameters[0], parameters[0] + p);
    for (double& x : u) x = std::clamp(x, 0.0, 1.0);
    std::optional<std::vector<double>> r;
    if (u == cached_u_ && cached_r_)
      r = cached_r_;
    else
      r = evaluator_.residuals(u);
    cached_u_ = u;
    cached_r_ = r;
    if (!r) return false;
    std::copy(r->begin(), r->end(), residuals);
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      Eigen::MatrixXd J;
      if (!evaluator_.jacobian(u, *r, J)) return false;
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
          jacobians[0], J.rows(), J.cols()) = J;
    }
    return true;
  }

 private:
  Evaluator& evaluator_;
  mutable std::vector<double> cached_u_;
  mutable std::optional<std::vector<double>> cached_r_;
};

class CeresProgress final : public ceres::IterationCallback {
 public:
  CeresProgress(RefineContext& context, const std::vector<double>& u) : context_(context), u_(u) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    context_.record(summary.iteration, u_, 2.0 * summary.cost);
    return ceres::SOLVER_CONTINUE;
  }

 private:
  RefineContext& context_;
  const std::vector<double>& u_;
};

std::string refine_ceres(const CalibrationProblem& problem, RefineContext& context,
                         std::vector<double>& u, int& iterations) {
  ceres::Problem ceres_problem;
  ceres_problem.AddResidualBlock(new MisfitCost(context.evaluator, u.size()), nullptr, u.data());
  for (int i = 0; i < static_cast<int>(u.size()); ++i) {
    ceres_problem.SetParameterLowerBound(u.data(), i, 0.0);
    ceres_problem.SetParameterUpperBound(u.data(), i, 1.0);
  }
  ceres::Solver::Options options;
  options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = problem.max_iterations;
  // The misfit carries the integrator's error (relative 1e-3 per step) and the noise of the
  // data: a relative change below 1e-5 is no progress worth another Jacobian.
  options.function_tolerance = 1e-5;
  options.parameter_tolerance = 1e-4;
  options.gradient_tolerance = 1e-8;
  options.num_threads = 1;  // the Evaluator runs the element tests in parallel itself
  options.logging_type = ceres::SILENT;
  options.update_state_every_iteration = true;
  CeresProgress callback(context, u);
  options.callbacks.push_back(&callback);
  ceres::Solver::Summary summary;
  ceres::Solve(options, &ceres_problem, &summary);
  iterations = static_cast<int>(summary.iterations.size()) - 1;
  return fmt::format("Ceres Levenberg-Marquardt: {} ({} iterations, {} successful)",
                     summary.message, iterations, summary.num_successful_steps);
}

std::string refine_nlopt(const CalibrationProblem& problem, RefineContext& context,
                         std::vector<double>& u, int& iterations) {
  const unsigned p = static_cast<unsigned>(u.size());
  nlopt::opt optimiser(nlopt::LN_BOBYQA, p);
  optimiser.set_lower_bounds(std::vector<double>(p, 0.0));
  optimiser.set_upper_bounds(std::vector<double>(p, 1.0));
  optimiser.set_initial_step(0.05);
  optimiser.set_ftol_rel(1e-5);
  optimiser.set_xtol_abs(1e-4);
  // Comparable with Ceres' limit: one Levenberg-Marquardt iteration costs p + 1 evaluations.
  const int max_evaluations = problem.max_iterations * static_cast<int>(p + 1);
  optimiser.set_maxeval(max_evaluations);
  context.max_steps = max_evaluations;
  struct Data {
    RefineContext* context;
    int evaluations = 0;
  } data{&context};
  optimiser.set_min_objective(
      [](const std::vector<double>& x, std::vector<double>&, void* raw) {
        Data& d = *static_cast<Data*>(raw);
        const auto r = d.context->evaluator.residuals(x);
        // An impossible set or a failed test: a misfit far above any real one.
        const double misfit = r ? sum_of_squares(*r) : 1e6;
        d.context->record(++d.evaluations, x, misfit);
        return misfit;
      },
      &data);
  double value = 0.0;
  std::string outcome;
  try {
    const nlopt::result result = optimiser.optimize(u, value);
    outcome = result == nlopt::SUCCESS           ? "converged"
              : result == nlopt::MAXEVAL_REACHED ? "evaluation limit reached"
              : result == nlopt::FTOL_REACHED    ? "misfit change below tolerance"
              : result == nlopt::XTOL_REACHED    ? "parameter change below tolerance"
                                                 : fmt::format("result code {}", int(result));
  } catch (const std::exception& e) {
    outcome = std::string("stopped: ") + e.what();
    u = context.best_u;
  }
  iterations = data.evaluations;
  return fmt::format("NLopt BOBYQA: {} ({} evaluations)", outcome, data.evaluations);
}

// The sensitivity at the optimum from the Jacobian J (normalised coordinates).
void sensitivity(const CalibrationProblem& problem, const std::vector<double>& u,
                 const std::vector<double>& r, const Eigen::MatrixXd& J, FitResult& result) {
  const double misfit = sum_of_squares(r);
  const Eigen::Index m = J.rows(), p = J.cols();
  const double sigma2 = misfit / static_cast<double>(std::max<Eigen::Index>(1, m - p));
  const Eigen::MatrixXd JtJ = J.transpose() * J;
  // A pseudo-inverse: a direction the data do not see has no finite error.
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(JtJ);
  const double largest = eigen.eigenvalues().cwiseAbs().maxCoeff();
  Eigen::VectorXd inverse_values = eigen.eigenvalues();
  bool singular = false;
  for (Eigen::Index i = 0; i < p; ++i) {
    if (eigen.eigenvalues()[i] > 1e-12 * largest) {
      inverse_values[i] = 1.0 / eigen.eigenvalues()[i];
    } else {
      inverse_values[i] = 0.0;
      singular = true;
    }
  }
  const Eigen::MatrixXd covariance = sigma2 * eigen.eigenvectors() * inverse_values.asDiagonal() *
                                     eigen.eigenvectors().transpose();
  for (Eigen::Index j = 0; j < p; ++j) {
    const FreeParameter& f = problem.free[static_cast<std::size_t>(j)];
    Sensitivity s;
    s.id = f.id;
    const double column = J.col(j).squaredNorm();
    s.misfit_rise_10pct = misfit > 0.0 ? 0.01 * column / misfit : 0.0;
    const double std_u = std::sqrt(std::max(0.0, covariance(j, j)));
    const double value = f.value(u[static_cast<std::size_t>(j)]);
    const double dvalue_du =
        f.log_scale() ? value * std::log(f.upper / f.lower) : f.upper - f.lower;
    s.standard_error = std_u * dvalue_du;
    s.standard_error_fraction = std_u * dvalue_du / (f.upper - f.lower);
    if (column < 1e-10 * std::max(1e-30, JtJ.diagonal().maxCoeff())) {
      s.determined = false;
      s.note = "the data do not depend on it";
    } else if (std_u > 0.05) {
      s.determined = false;
      s.note = "poorly determined: standard error above 5 % of its bound range";
    }
    const double u_j = u[static_cast<std::size_t>(j)];
    if (u_j < 1e-3 || u_j > 1.0 - 1e-3)
      s.note += (s.note.empty() ? "" : "; ") + std::string("at a bound");
    result.sensitivity.push_back(s);
  }
  if (singular)
    result.warnings.push_back(
        "the Jacobian is singular: some combination of the free parameters is not determined "
        "by the data");
  for (Eigen::Index a = 0; a < p; ++a)
    for (Eigen::Index b = a + 1; b < p; ++b) {
      const double d = std::sqrt(covariance(a, a) * covariance(b, b));
      if (!(d > 0.0)) continue;
      const double c = covariance(a, b) / d;
      if (std::abs(c) > 0.9)
        result.correlations.push_back(
            fmt::format("{} ~ {}: {:+.3f}", parameter_name(problem.free[std::size_t(a)].id),
                        parameter_name(problem.free[std::size_t(b)].id), c));
    }
}

}  // namespace

FitResult calibrate(const CalibrationProblem& problem, const FitObserver& observer) {
  FitResult result;
  result.method = problem.method;
  if (problem.free.empty()) throw Error("calibration: no free parameter");
  const auto start = Clock::now();
  Evaluator evaluator(problem);
  const auto report = [&](const std::string& stage, const std::string& message) {
    if (!observer) return;
    FitProgress p;
    p.stage = stage;
    p.runs = evaluator.runs();
    p.seconds = seconds_since(start);
    p.message = message;
    observer(p);
  };

  // Stage 1.
  report("start", problem.physics_start ? "physics-ordered start from the measured curves"
                                        : "start set as given (physics_start = false)");
  result.start =
      problem.physics_start ? physics_start(problem, evaluator, result.start_notes) : problem.base;
  for (const FreeParameter& f : problem.free)
    if (f.start) set(result.start, f.id, *f.start);
  std::vector<double> u = coordinates_of(problem, result.start);
  const auto r_start = evaluator.residuals(u);
  if (!r_start)
    throw Error(
        "calibration: the model fails on a test with the starting set (or the set is "
        "impossible); give start values or bounds closer to the data");
  result.start_misfit = sum_of_squares(*r_start);
  result.history.push_back({"start", 0, evaluator.runs(), seconds_since(start), result.start_misfit,
                            parameters_at(problem, u)});
  result.runs_start = evaluator.runs();
  result.seconds_start = seconds_since(start);

  // Stage 2.
  RefineContext context{
      evaluator, observer, start, result.history, problem.max_iterations, result.start_misfit, u};
  if (problem.method == "nlopt-bobyqa")
    result.termination = refine_nlopt(problem, context, u, result.iterations);
  else
    result.termination = refine_ceres(problem, context, u, result.iterations);
  for (double& x : u) x = std::clamp(x, 0.0, 1.0);
  auto r = evaluator.residuals(u);
  if (!r || sum_of_squares(*r) > context.best_misfit) {
    u = context.best_u;
    r = evaluator.residuals(u);
  }
  if (!r) throw Error("calibration: the model fails with the fitted set");
  result.fitted = parameters_at(problem, u);
  result.final_misfit = sum_of_squares(*r);
  result.runs_refine = evaluator.runs() - result.runs_start;
  result.seconds_refine = seconds_since(start) - result.seconds_start;

  // Sensitivity and the fit of each quantity.
  report("sensitivity", "Jacobian at the fitted set");
  Eigen::MatrixXd J;
  if (evaluator.jacobian(u, *r, J))
    sensitivity(problem, u, *r, J, result);
  else
    result.warnings.push_back("no sensitivity: the model fails next to the fitted set");
  const ModelPtr model = make_hypoplastic(result.fitted, problem.integrator);
  for (std::size_t k = 0; k < problem.tests.size(); ++k) {
    const auto simulated = simulate(problem.tests[k], model);
    if (!simulated) continue;
    for (std::size_t i = 0; i < problem.tests[k].quantities.size(); ++i)
      result.quantities.push_back(
          {k, i, normalised_rms(problem.tests[k].quantities[i], (*simulated)[i]), (*simulated)[i]});
  }
  result.runs = evaluator.runs();
  result.runs_sensitivity = result.runs - result.runs_start - result.runs_refine;
  result.seconds = seconds_since(start);
  result.seconds_sensitivity = result.seconds - result.seconds_start - result.seconds_refine;
  return result;
}

}  // namespace pilempm::calibration
