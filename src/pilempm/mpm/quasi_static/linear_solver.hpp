#pragma once
// The sparse direct solver of the quasi-static analysis: LU of a general (unsymmetric) sparse
// matrix, from Eigen (SparseLU, supernodal, COLAMD ordering) or from SuiteSparse (UMFPACK,
// multifrontal, through Eigen's UmfPackLU wrapper) when the build found it
// (PILEMPM_HAVE_UMFPACK). docs/quasi-static.md compares the two.
#include <Eigen/SparseCore>
#include <memory>
#include <string>

namespace pilempm::mpm::quasi_static {

enum class LinearSolverKind {
  sparse_lu,  ///< Eigen::SparseLU with COLAMD ordering
  umfpack,    ///< SuiteSparse UMFPACK (only where built with it)
};

/// Whether this build has UMFPACK.
bool umfpack_available();
std::string to_string(LinearSolverKind kind);

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

class LinearSolver {
 public:
  LinearSolver();
  ~LinearSolver();
  LinearSolver(LinearSolver&&) noexcept;
  LinearSolver& operator=(LinearSolver&&) noexcept;

  /// Throws InvalidValue for UMFPACK in a build without it.
  void set_kind(LinearSolverKind kind);
  LinearSolverKind kind() const { return kind_; }

  /// Orders the pattern of `matrix` (once per pattern) and factorises it. Returns false when the
  /// matrix is singular to the solver.
  bool factorize(const SparseMatrix& matrix, bool new_pattern);
  /// x = A^-1 b with the last factorisation.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

 private:
  struct Backend;
  LinearSolverKind kind_ = LinearSolverKind::sparse_lu;
  std::unique_ptr<Backend> backend_;
};

}  // namespace pilempm::mpm::quasi_static
