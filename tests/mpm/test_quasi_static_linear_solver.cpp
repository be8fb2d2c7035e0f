// The quasi-static analysis's sparse direct solvers (linear_solver.hpp): every backend this build
// has solves an unsymmetric system to round-off, refactorises new values on a kept pattern, and
// reports a singular matrix instead of returning a solution.
#include <gtest/gtest.h>

#include <vector>

#include "pilempm/core/error.hpp"
#include "pilempm/mpm/quasi_static/linear_solver.hpp"
#include "pilempm/mpm/quasi_static/quasi_static_solver.hpp"

namespace pilempm::mpm::quasi_static {
namespace {

std::vector<LinearSolverKind> available_kinds() {
  std::vector<LinearSolverKind> kinds;
  for (const LinearSolverKind kind : kLinearSolverKinds)
    if (linear_solver_available(kind)) kinds.push_back(kind);
  return kinds;
}

// Convection-diffusion on an n x n grid (5-point stencil, upwinded convection of strength
// `wind`): unsymmetric, diagonally dominant, like the Newton matrices' sparsity in kind.
SparseMatrix convection_diffusion(int n, double wind) {
  std::vector<Eigen::Triplet<double>> entries;
  const auto index = [n](int i, int j) { return i * n + j; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int row = index(i, j);
      entries.emplace_back(row, row, 4.0 + wind);
      if (i > 0) entries.emplace_back(row, index(i - 1, j), -1.0 - wind);
      if (i + 1 < n) entries.emplace_back(row, index(i + 1, j), -1.0);
      if (j > 0) entries.emplace_back(row, index(i, j - 1), -1.0);
      if (j + 1 < n) entries.emplace_back(row, index(i, j + 1), -1.0 + 0.3 * wind);
    }
  SparseMatrix matrix(n * n, n * n);
  matrix.setFromTriplets(entries.begin(), entries.end());
  matrix.makeCompressed();
  return matrix;
}

double relative_error(const Eigen::VectorXd& x, const Eigen::VectorXd& exact) {
  return (x - exact).norm() / exact.norm();
}

TEST(QuasiStaticLinearSolver, EveryBackendSolvesAnUnsymmetricSystemAndRefactorisesNewValues) {
  const SparseMatrix first = convection_diffusion(20, 0.5);
  ASSERT_GT((SparseMatrix(first.transpose()) - first).norm(), 1.0);  // unsymmetric
  // The same pattern with other values: what the later Newton iterations of an increment give.
  const SparseMatrix second = convection_diffusion(20, 2.0);
  const Eigen::VectorXd exact = Eigen::VectorXd::LinSpaced(first.rows(), -1.0, 3.0);
  for (const LinearSolverKind kind : available_kinds()) {
    SCOPED_TRACE(to_string(kind));
    LinearSolver solver;
    solver.set_kind(kind);
    ASSERT_TRUE(solver.factorize(first, true));
    EXPECT_LT(relative_error(solver.solve(first * exact), exact), 1e-12);
    ASSERT_TRUE(solver.factorize(second, false));
    EXPECT_LT(relative_error(solver.solve(second * exact), exact), 1e-12);
    // A second right-hand side on the same factors.
    const Eigen::VectorXd other = Eigen::VectorXd::Constant(first.rows(), 0.25);
    EXPECT_LT(relative_error(solver.solve(second * other), other), 1e-12);
  }
}

TEST(QuasiStaticLinearSolver, ASingularMatrixIsReportedNotSolved) {
  const SparseMatrix matrix = convection_diffusion(6, 1.0);
  // Unknown 7 without any stiffness (row and column empty): a node that nothing supports.
  std::vector<Eigen::Triplet<double>> entries;
  for (int c = 0; c < matrix.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(matrix, c); it; ++it)
      if (it.row() != 7 && it.col() != 7) entries.emplace_back(it.row(), it.col(), it.value());
  SparseMatrix singular(matrix.rows(), matrix.cols());
  singular.setFromTriplets(entries.begin(), entries.end());
  singular.makeCompressed();
  for (const LinearSolverKind kind : available_kinds()) {
    SCOPED_TRACE(to_string(kind));
    LinearSolver solver;
    solver.set_kind(kind);
    EXPECT_FALSE(solver.factorize(singular, true));
    // The same solver recovers on a regular matrix of another pattern.
    ASSERT_TRUE(solver.factorize(matrix, true));
    const Eigen::VectorXd exact = Eigen::VectorXd::Ones(matrix.rows());
    EXPECT_LT(relative_error(solver.solve(matrix * exact), exact), 1e-12);
  }
}

TEST(QuasiStaticLinearSolver, TheDefaultIsTheFastestTheBuildHasAndAMissingOneIsRefused) {
  const LinearSolverKind best = mumps_available()     ? LinearSolverKind::mumps
                                : umfpack_available() ? LinearSolverKind::umfpack
                                                      : LinearSolverKind::sparse_lu;
  EXPECT_EQ(default_linear_solver(), best);
  EXPECT_EQ(Settings{}.linear_solver, best);
  for (const LinearSolverKind kind : {LinearSolverKind::umfpack, LinearSolverKind::mumps}) {
    if (linear_solver_available(kind)) continue;
    LinearSolver solver;
    EXPECT_THROW(solver.set_kind(kind), InvalidValue) << to_string(kind);
    Settings settings;
    settings.linear_solver = kind;
    EXPECT_THROW(settings.validate(), InvalidValue) << to_string(kind);
  }
}

}  // namespace
}  // namespace pilempm::mpm::quasi_static
