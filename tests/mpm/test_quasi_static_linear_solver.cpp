// The quasi-static analysis's sparse direct solvers (linear_solver.hpp): every backend this build
// has solves an unsymmetric system to round-off, refactorises new values on a kept pattern, and
// reports a singular matrix instead of returning a solution; the mixed-precision MUMPS refines its
// single-precision solutions to the stated residual, and falls back to a double-precision LU
// where the matrix is too ill-conditioned for single precision.
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
  const LinearSolverKind best = mumps_available()     ? LinearSolverKind::mumps_mixed
                                : umfpack_available() ? LinearSolverKind::umfpack
                                                      : LinearSolverKind::sparse_lu;
  EXPECT_EQ(default_linear_solver(), best);
  EXPECT_EQ(Settings{}.linear_solver, best);
  for (const LinearSolverKind kind :
       {LinearSolverKind::umfpack, LinearSolverKind::mumps, LinearSolverKind::mumps_mixed}) {
    if (linear_solver_available(kind)) continue;
    LinearSolver solver;
    EXPECT_THROW(solver.set_kind(kind), InvalidValue) << to_string(kind);
    Settings settings;
    settings.linear_solver = kind;
    EXPECT_THROW(settings.validate(), InvalidValue) << to_string(kind);
  }
}

// A 1D Laplacian with Neumann ends (singular: the constant is its null vector) plus `shift` on
// the diagonal and an upwind term: cond ~ 4 / shift, unsymmetric.
SparseMatrix shifted_neumann_chain(int n, double shift) {
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < n; ++i) {
    double diagonal = shift;
    if (i > 0) {
      entries.emplace_back(i, i - 1, -1.2);
      diagonal += 1.2;
    }
    if (i + 1 < n) {
      entries.emplace_back(i, i + 1, -0.8);
      diagonal += 0.8;
    }
    entries.emplace_back(i, i, diagonal);
  }
  SparseMatrix matrix(n, n);
  matrix.setFromTriplets(entries.begin(), entries.end());
  matrix.makeCompressed();
  return matrix;
}

double relative_residual(const SparseMatrix& a, const Eigen::VectorXd& x,
                         const Eigen::VectorXd& b) {
  return (b - a * x).norm() / b.norm();
}

TEST(QuasiStaticLinearSolver, MixedPrecisionRefinesItsSingleLuToTheStatedResidual) {
  if (!mumps_available()) GTEST_SKIP() << "this build has no MUMPS";
  const SparseMatrix matrix = convection_diffusion(30, 1.0);
  const Eigen::VectorXd b = matrix * Eigen::VectorXd::LinSpaced(matrix.rows(), 1.0, 2.0);
  LinearSolver solver;
  solver.set_kind(LinearSolverKind::mumps_mixed);
  ASSERT_TRUE(solver.factorize(matrix, true));
  const Eigen::VectorXd x = solver.solve(b);
  EXPECT_LE(relative_residual(matrix, x, b), kRefinementTolerance);
  // A single-precision solve alone leaves about 1e-7 (float's round-off): the refinement ran, and
  // on this well-conditioned matrix without the double-precision LU.
  EXPECT_GE(solver.counts().precision_solves, 2);
  EXPECT_LE(solver.counts().precision_solves, kMaxRefinementSolves);
  EXPECT_EQ(solver.counts().double_fallbacks, 0);
  EXPECT_EQ(solver.counts().factorisations, 1);
  EXPECT_EQ(solver.counts().solves, 1);
}

TEST(QuasiStaticLinearSolver, MixedPrecisionFallsBackToDoubleWhereSingleCannotConverge) {
  if (!mumps_available()) GTEST_SKIP() << "this build has no MUMPS";
  // cond ~ 1e11: single precision's LU (round-off 6e-8) cannot refine it, double's (1e-16) can.
  const SparseMatrix matrix = shifted_neumann_chain(200, 1.0e-11);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(matrix.rows(), -1.0, 1.0);
  LinearSolver mixed, exact;
  mixed.set_kind(LinearSolverKind::mumps_mixed);
  exact.set_kind(LinearSolverKind::mumps);
  ASSERT_TRUE(mixed.factorize(matrix, true));
  ASSERT_TRUE(exact.factorize(matrix, true));
  const Eigen::VectorXd x = mixed.solve(b);
  EXPECT_EQ(mixed.counts().double_fallbacks, 1);
  // The solution is huge (b is not orthogonal to the near null space), so no LU reaches 1e-10
  // ||b||: the answer is the double-precision LU's, to its backward error.
  const Eigen::VectorXd reference = exact.solve(b);
  EXPECT_GT(relative_residual(matrix, reference, b), kRefinementTolerance);
  EXPECT_LT(relative_error(x, reference), 1e-9);
  const auto backward_error = [&](const Eigen::VectorXd& y, const Eigen::VectorXd& rhs) {
    return (rhs - matrix * y).norm() / (matrix.norm() * y.norm() + rhs.norm());
  };
  EXPECT_LT(backward_error(x, b), 1e-14);
  // The double-precision LU serves the matrix's next solves; a new matrix tries single again.
  const Eigen::VectorXd other = Eigen::VectorXd::Ones(matrix.rows());
  EXPECT_LT(backward_error(mixed.solve(other), other), 1e-14);
  EXPECT_EQ(mixed.counts().double_fallbacks, 1);
  const SparseMatrix easy = shifted_neumann_chain(200, 1.0);
  ASSERT_TRUE(mixed.factorize(easy, false));
  EXPECT_LE(relative_residual(easy, mixed.solve(b), b), kRefinementTolerance);
  EXPECT_EQ(mixed.counts().double_fallbacks, 1);
}

}  // namespace
}  // namespace pilempm::mpm::quasi_static
