// Quasi-static analysis (docs/quasi-static.md): time per load step and per Newton iteration, by
// part (model updates with tangents, assembly, factorisation and solve), on the small pile
// problem (pile_problem.hpp) in Mohr-Coulomb sand, the pile pushed by D/20 per step.
//
//   bench_quasi_static [cells_per_d] [threads] [sparse-lu|umfpack] [steps] [steps_per_d]
//   bench_quasi_static compare [cells_per_d] [steps] [repeats]
//
// `compare` pushes the pile `steps` steps, then factorises and solves the last Newton matrix
// with Eigen's SparseLU and with UMFPACK alternately, `repeats` times each, and prints the
// fastest and the median time of each (pattern analysis + numeric factorisation + solve, and
// the numeric factorisation + solve alone, as in the later iterations of an increment).
//
// The particle count follows from cells_per_d (5 D x 8 D sand, 2 x 2 per cell): 4 -> 2 560,
// 7 -> 7 840, 12 -> 23 040, 14 -> 31 360. Prints one line per load step and the means.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "pilempm/constitutive/mohr_coulomb/mohr_coulomb.hpp"
#include "pilempm/mpm/quasi_static/pile_problem.hpp"

using namespace pilempm;
using namespace pilempm::mpm;
using namespace pilempm::mpm::quasi_static;

namespace {

MohrCoulombParameters sand() {
  MohrCoulombParameters mc;
  mc.young_modulus = 50.0e6;
  mc.poisson_ratio = 0.3;
  mc.cohesion = 1.0e3;
  mc.friction_angle_deg = 35.0;
  mc.dilatancy_angle_deg = 5.0;
  return mc;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int compare_solvers(int cells_per_d, int steps, int repeats) {
  PileProblem problem;
  problem.cells_per_d = cells_per_d;
  problem.model = std::make_shared<MohrCoulomb>(sand());
  problem.settings.threads = 1;
  QuasiStaticSolver solver = problem.build();
  LoadStep load;
  load.gravity_multiplier = problem.gravity_multiplier;
  for (int step = 0; step <= steps; ++step) {
    load.body_displacement = {Vec2(0.0, step == 0 ? 0.0 : -problem.diameter / 20.0)};
    if (!solver.solve_step(load).converged) {
      std::printf("step %d failed\n", step);
      return 1;
    }
  }
  const SparseMatrix& matrix = solver.last_matrix();
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(matrix.rows());
  std::printf("particles %zu, matrix %ld x %ld, %ld non-zeros\n", solver.particles().size(),
              long(matrix.rows()), long(matrix.cols()), long(matrix.nonZeros()));
  std::vector<LinearSolverKind> kinds = {LinearSolverKind::sparse_lu};
  if (umfpack_available()) kinds.push_back(LinearSolverKind::umfpack);
  std::vector<std::vector<double>> full(kinds.size()), numeric(kinds.size());
  std::vector<double> residual(kinds.size(), 0.0);
  for (int r = 0; r < repeats; ++r)
    for (std::size_t k = 0; k < kinds.size(); ++k) {
      LinearSolver linear;
      linear.set_kind(kinds[k]);
      auto start = std::chrono::steady_clock::now();
      linear.factorize(matrix, true);
      Eigen::VectorXd x = linear.solve(b);
      full[k].push_back(seconds_since(start));
      start = std::chrono::steady_clock::now();
      linear.factorize(matrix, false);
      x = linear.solve(b);
      numeric[k].push_back(seconds_since(start));
      residual[k] = (matrix * x - b).norm() / b.norm();
    }
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    std::sort(full[k].begin(), full[k].end());
    std::sort(numeric[k].begin(), numeric[k].end());
    std::printf(
        "%-10s analyse+factorise+solve: min %.5f s, median %.5f s; factorise+solve: min "
        "%.5f s, median %.5f s; relative residual %.1e\n",
        to_string(kinds[k]).c_str(), full[k].front(), full[k][full[k].size() / 2],
        numeric[k].front(), numeric[k][numeric[k].size() / 2], residual[k]);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "compare")
    return compare_solvers(argc > 2 ? std::atoi(argv[2]) : 4, argc > 3 ? std::atoi(argv[3]) : 6,
                           argc > 4 ? std::atoi(argv[4]) : 20);
  const int cells_per_d = argc > 1 ? std::atoi(argv[1]) : 4;
  const int threads = argc > 2 ? std::atoi(argv[2]) : 1;
  const std::string solver_name = argc > 3 ? argv[3] : "sparse-lu";
  const int steps = argc > 4 ? std::atoi(argv[4]) : 10;
  const int steps_per_d = argc > 5 ? std::atoi(argv[5]) : 20;
  PileProblem problem;
  problem.cells_per_d = cells_per_d;
  problem.model = std::make_shared<MohrCoulomb>(sand());
  problem.settings.threads = threads;
  problem.settings.linear_solver =
      solver_name == "umfpack" ? LinearSolverKind::umfpack : LinearSolverKind::sparse_lu;
  QuasiStaticSolver solver = problem.build();
  std::printf("particles %zu, threads %d, linear solver %s\n", solver.particles().size(), threads,
              solver_name.c_str());
  std::printf(
      "step,depth_D,head_force_N,iterations,cuts,unknowns,seconds,material_s,assembly_s,"
      "factorisation_s\n");
  double total = 0.0, material = 0.0, assembly = 0.0, factorisation = 0.0;
  int iterations = 0;
  LoadStep load;
  load.gravity_multiplier = problem.gravity_multiplier;
  for (int step = 0; step <= steps; ++step) {
    // Step 0: the geostatic equilibrium; then the pile moves down by D/steps_per_d per step.
    load.body_displacement = {Vec2(0.0, step == 0 ? 0.0 : -problem.diameter / steps_per_d)};
    const auto start = std::chrono::steady_clock::now();
    const LoadStepResult r = solver.solve_step(load);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (std::getenv("QS_VERBOSE"))
      for (const SubIncrementRecord& sub : r.sub_increments) {
        std::printf("  fraction %.4f R0/F %.2e:", sub.fraction,
                    sub.initial_residual / sub.reference_force);
        for (const IterationRecord& it : sub.iterations)
          std::printf(" %.1e/%.1e(%.2f)", it.residual_norm / sub.reference_force, it.energy_norm,
                      it.line_search);
        std::printf("\n");
      }
    if (!r.converged) {
      std::printf("step %d failed: %s\n", step, r.message.c_str());
      return 1;
    }
    const double depth = -solver.rigid_body(0).displacement().y() / problem.diameter;
    std::printf("%d,%.3f,%.3f,%d,%d,%d,%.4f,%.4f,%.4f,%.4f\n", step, depth,
                2.0 * kPi * solver.body_force(0).total.y(), r.iterations, r.cuts, r.unknowns,
                seconds, r.seconds_material, r.seconds_assembly, r.seconds_factorisation);
    if (step == 0) continue;
    total += seconds;
    material += r.seconds_material;
    assembly += r.seconds_assembly;
    factorisation += r.seconds_factorisation;
    iterations += r.iterations;
  }
  std::printf(
      "mean per load step %.4f s, per iteration %.4f s (%.1f iterations per step); "
      "shares: material %.0f %%, assembly %.0f %%, factorisation+solve %.0f %%\n",
      total / steps, total / iterations, double(iterations) / steps, 100.0 * material / total,
      100.0 * assembly / total, 100.0 * factorisation / total);
  return 0;
}
