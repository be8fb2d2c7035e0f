// Quasi-static analysis (docs/quasi-static.md): time per load step and per Newton iteration, by
// part (model updates with tangents, assembly, factorisation and solve), on the small pile
// problem (pile_problem.hpp) in Mohr-Coulomb sand, the pile pushed by D/20 per step.
//
//   bench_quasi_static [cells_per_d] [threads] [sparse-lu|umfpack|mumps] [steps] [steps_per_d]
//   bench_quasi_static compare [cells_per_d] [steps] [repeats]
//   bench_quasi_static footing <csv> [cells_under_footing] [friction] [steps_per_cell] [cells]
//   bench_quasi_static pile <csv> [mohr-coulomb|hypoplastic] [cells_per_d] [steps_per_d] [depth_d]
//
// `footing` and `pile` write the curves of the quasi-static verifications 4 and 7
// (docs/verification.md §9; tools/plot/plot_quasi_static.py draws them): the strip footing on
// Tresca soil (footing_problem.hpp) pushed `cells` cells in `steps_per_cell` steps per cell, and
// the pile pushed `depth_d` D in `steps_per_d` steps per D. One CSV row per load step.
//
// `compare` pushes the pile `steps` steps, then factorises and solves the last Newton matrix
// with each solver the build has (MUMPS, UMFPACK, SparseLU) in turn, `repeats` times each, and
// prints the fastest and the median time of each (pattern analysis + numeric factorisation + solve,
// and the numeric factorisation + solve alone, as in the later iterations of an increment).
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

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/constitutive/mohr_coulomb/mohr_coulomb.hpp"
#include "pilempm/mpm/quasi_static/footing_problem.hpp"
#include "pilempm/mpm/quasi_static/load_path.hpp"
#include "pilempm/mpm/quasi_static/pile_problem.hpp"

using namespace pilempm;
using namespace pilempm::mpm;
using namespace pilempm::mpm::quasi_static;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int compare_solvers(int cells_per_d, int steps, int repeats) {
  PileProblem problem;
  problem.cells_per_d = cells_per_d;
  problem.model = pile_mohr_coulomb_sand();
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
  std::vector<LinearSolverKind> kinds;
  for (const LinearSolverKind kind : kLinearSolverKinds)
    if (linear_solver_available(kind)) kinds.push_back(kind);
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

// Diagnostic overrides of the settings (before/after comparisons in docs/quasi-static.md):
// QS_VERTEX_RADIUS (ContactSettings::vertex_radius), QS_PENALTY (penalty_factor), QS_BBAR
// (Settings::volumetric_averaging, 0 or 1), QS_STEP_LIMIT (Settings::step_limit), QS_TURNING
// (ContactSettings::turning_terms, 0 or 1), QS_SPIN (Settings::spin_terms, 0 or 1).
void apply_environment(Settings& settings) {
  if (const char* v = std::getenv("QS_VERTEX_RADIUS"))
    settings.contact.vertex_radius = std::atof(v);
  if (const char* v = std::getenv("QS_PENALTY")) settings.contact.penalty_factor = std::atof(v);
  if (const char* v = std::getenv("QS_BBAR")) settings.volumetric_averaging = std::atoi(v) != 0;
  if (const char* v = std::getenv("QS_STEP_LIMIT")) settings.step_limit = std::atof(v);
  if (const char* v = std::getenv("QS_FLOOR_STIFFNESS")) settings.floor_stiffness = std::atof(v);
  if (const char* v = std::getenv("QS_APEX_STIFFNESS")) settings.apex_stiffness = std::atof(v);
  if (const char* v = std::getenv("QS_FORCE_TOLERANCE")) settings.force_tolerance = std::atof(v);
  if (const char* v = std::getenv("QS_MAX_ITERATIONS")) settings.max_iterations = std::atoi(v);
  if (const char* v = std::getenv("QS_ACCEPT")) settings.accept_tolerance = std::atof(v);
  if (const char* v = std::getenv("QS_ACCEPT_AFTER")) settings.accept_after = std::atoi(v);
  if (const char* v = std::getenv("QS_SMOOTHING")) settings.contact.smoothing = std::atof(v);
  if (const char* v = std::getenv("QS_TURNING")) settings.contact.turning_terms = std::atoi(v) != 0;
  if (const char* v = std::getenv("QS_SPIN")) settings.spin_terms = std::atoi(v) != 0;
  if (const char* v = std::getenv("QS_TANGENT"))  // "perturbation": not the model's own
    if (std::string(v) == "perturbation") settings.tangent = TangentKind::perturbation;
  if (const char* v = std::getenv("QS_TANGENTIAL_RATIO"))
    settings.contact.tangential_ratio = std::atof(v);
}

// With QS_VERBOSE set: per sub-increment ||R||/F_ref, the energy norm, the line search's step
// and the contact points (in contact, slipping, changed) of each iteration.
void print_iterations(const LoadStepResult& r) {
  if (std::getenv("QS_VERBOSE") == nullptr) return;
  for (const SubIncrementRecord& sub : r.sub_increments) {
    std::printf("  fraction %.4f R0/F %.2e:", sub.fraction,
                sub.initial_residual / sub.reference_force);
    for (const IterationRecord& it : sub.iterations)
      std::printf(" %.1e/%.1e(%.2f;%d,%d,%d;f%d)", it.residual_norm / sub.reference_force,
                  it.energy_norm, it.line_search, it.contact_points, it.slipping_points,
                  it.contact_changes, it.floor_particles);
    std::printf("\n");
  }
}

std::FILE* open_csv(const char* path) {
  std::FILE* file = std::fopen(path, "w");
  if (file == nullptr) std::fprintf(stderr, "cannot write %s\n", path);
  return file;
}

int footing_curve(const char* path, int cells_under_footing, double friction, int steps_per_cell,
                  int cells) {
  StripFootingProblem problem;
  problem.cells_under_footing = cells_under_footing;
  problem.friction = friction;
  apply_environment(problem.settings);
  QuasiStaticSolver solver = problem.build();
  const double h = problem.cell();
  std::FILE* csv = open_csv(path);
  if (csv == nullptr) return 1;
  std::fprintf(csv,
               "settlement_m,settlement_over_cell,pressure_over_c,iterations,cuts,"
               "penetration_over_cell\n");
  // One row per converged step, written as it comes (a long run can be read while it goes on).
  auto row = [&](const LoadStepResult& r) {
    print_iterations(r);
    if (!r.converged) return;
    const double travel = -solver.rigid_body(0).displacement().y();
    std::fprintf(csv, "%.6e,%.6f,%.6f,%d,%d,%.3e\n", travel, travel / h,
                 solver.body_force(0).total.y() / problem.half_width / problem.cohesion,
                 r.iterations, r.cuts, solver.max_penetration() / h);
    std::fflush(csv);
  };
  const auto start = std::chrono::steady_clock::now();
  const std::vector<PushPoint> points =
      push_body(solver, 0, Vec2(0.0, -h / steps_per_cell), steps_per_cell * cells, 0.0, row);
  std::fclose(csv);
  std::printf("footing: %zu steps in %.1f s%s\n", points.size(), seconds_since(start),
              points.back().converged ? "" : (", failed: " + points.back().message).c_str());
  return points.back().converged ? 0 : 1;
}

int pile_curve(const char* path, const std::string& sand, int cells_per_d, int steps_per_d,
               double depth_d) {
  PileProblem problem;
  problem.cells_per_d = cells_per_d;
  if (sand == "hypoplastic") {
    problem.model = pile_hypoplastic_sand();
    if (const char* v = std::getenv("QS_P_MIN")) {
      IntegratorSettings integrator;
      integrator.min_mean_stress = std::atof(v);
      problem.model = std::make_shared<Hypoplastic>(hypoplastic_set("modified-medium-dense"),
                                                    intergranular_strain_set("IGS3"), integrator);
    }
    problem.void_ratio = 0.68;
  } else if (const char* t = std::getenv("QS_TENSION_CUTOFF")) {
    MohrCoulombParameters mc =
        dynamic_cast<const MohrCoulomb&>(*pile_mohr_coulomb_sand()).parameters();
    mc.tension_cutoff = std::atof(t);
    problem.model = std::make_shared<MohrCoulomb>(mc);
  } else {
    problem.model = pile_mohr_coulomb_sand();
  }
  if (const char* v = std::getenv("QS_EMBEDMENT_D")) problem.embedment_in_d = std::atof(v);
  if (const char* v = std::getenv("QS_FRICTION")) problem.friction = std::atof(v);
  apply_environment(problem.settings);
  QuasiStaticSolver solver = problem.build();
  LoadStep geostatic;
  geostatic.gravity_multiplier = problem.gravity_multiplier;
  const LoadStepResult first = solver.solve_step(geostatic);
  print_iterations(first);
  if (!first.converged) {
    std::printf("the geostatic step failed: %s\n", first.message.c_str());
    return 1;
  }
  const double h = problem.diameter / cells_per_d;
  std::FILE* csv = open_csv(path);
  if (csv == nullptr) return 1;
  std::fprintf(csv, "depth_over_d,head_force_N,iterations,cuts,penetration_over_cell\n");
  const bool check = std::getenv("QS_CHECK_TANGENT") != nullptr;
  auto row = [&](const LoadStepResult& r) {
    print_iterations(r);
    if (!r.converged) return;
    if (check) {  // the Newton matrix against the residual's derivative at the next predictor
      LoadStep next;
      next.gravity_multiplier = problem.gravity_multiplier;
      next.body_displacement = {Vec2(0.0, -problem.diameter / steps_per_d)};
      const TangentCheck t = solver.check_tangent(next);
      std::printf(
          "tangent check: total %.2e material %.2e contact %.2e, worst at (%.4f, %.4f) %c\n",
          t.total, t.material, t.contact, t.worst_node.x(), t.worst_node.y(),
          t.worst_component == 0 ? 'x' : 'y');
    }
    std::fprintf(csv, "%.6f,%.6f,%d,%d,%.3e\n",
                 -solver.rigid_body(0).displacement().y() / problem.diameter,
                 2.0 * kPi * solver.body_force(0).total.y(), r.iterations, r.cuts,
                 solver.max_penetration() / h);
    std::fflush(csv);
  };
  const auto start = std::chrono::steady_clock::now();
  const int steps = static_cast<int>(std::lround(depth_d * steps_per_d));
  const std::vector<PushPoint> points =
      push_body(solver, 0, Vec2(0.0, -problem.diameter / steps_per_d), steps,
                problem.gravity_multiplier, row);
  std::fclose(csv);
  std::printf("pile (%s): %zu steps in %.1f s%s\n", sand.c_str(), points.size(),
              seconds_since(start),
              points.back().converged ? "" : (", failed: " + points.back().message).c_str());
  return points.back().converged ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 2 && std::string(argv[1]) == "footing")
    return footing_curve(argv[2], argc > 3 ? std::atoi(argv[3]) : 8,
                         argc > 4 ? std::atof(argv[4]) : 0.0, argc > 5 ? std::atoi(argv[5]) : 8,
                         argc > 6 ? std::atoi(argv[6]) : 3);
  if (argc > 2 && std::string(argv[1]) == "pile")
    return pile_curve(argv[2], argc > 3 ? argv[3] : "mohr-coulomb",
                      argc > 4 ? std::atoi(argv[4]) : 4, argc > 5 ? std::atoi(argv[5]) : 20,
                      argc > 6 ? std::atof(argv[6]) : 3.0);
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
  problem.model = pile_mohr_coulomb_sand();
  problem.settings.threads = threads;
  problem.settings.linear_solver =
      linear_solver_from_string(solver_name).value_or(LinearSolverKind::sparse_lu);
  apply_environment(problem.settings);
  QuasiStaticSolver solver = problem.build();
  std::printf("particles %zu, threads %d, linear solver %s\n", solver.particles().size(), threads,
              solver_name.c_str());
  std::printf(
      "step,depth_D,head_force_N,iterations,cuts,unknowns,seconds,material_s,assembly_s,"
      "factorisation_s,penetration_over_cell\n");
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
    print_iterations(r);
    if (!r.converged) {
      std::printf("step %d failed: %s\n", step, r.message.c_str());
      return 1;
    }
    const double depth = -solver.rigid_body(0).displacement().y() / problem.diameter;
    std::printf("%d,%.3f,%.3f,%d,%d,%d,%.4f,%.4f,%.4f,%.4f,%.2e\n", step, depth,
                2.0 * kPi * solver.body_force(0).total.y(), r.iterations, r.cuts, r.unknowns,
                seconds, r.seconds_material, r.seconds_assembly, r.seconds_factorisation,
                solver.max_penetration() * cells_per_d / problem.diameter);
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
