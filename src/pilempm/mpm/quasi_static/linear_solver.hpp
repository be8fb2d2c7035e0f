#pragma once
// The sparse direct solver of the quasi-static analysis: LU of a general (unsymmetric) sparse
// matrix, from MUMPS (sequential, multifrontal, AMD ordering) or SuiteSparse UMFPACK
// (multifrontal, through Eigen's UmfPackLU wrapper) when the build found them
// (PILEMPM_HAVE_MUMPS, PILEMPM_HAVE_UMFPACK), or from Eigen (SparseLU, supernodal, COLAMD
// ordering) always. docs/quasi-static.md, "The linear solver", compares them.
#include <Eigen/SparseCore>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace pilempm::mpm::quasi_static {

enum class LinearSolverKind {
  sparse_lu,  ///< Eigen::SparseLU with COLAMD ordering
  umfpack,    ///< SuiteSparse UMFPACK (only where built with it)
  mumps,      ///< MUMPS, sequential (only where built with it)
};
/// Every kind, fastest first (the order of default_linear_solver's choice).
inline constexpr std::array<LinearSolverKind, 3> kLinearSolverKinds = {
    LinearSolverKind::mumps, LinearSolverKind::umfpack, LinearSolverKind::sparse_lu};

/// Whether this build has UMFPACK.
bool umfpack_available();
/// Whether this build has MUMPS.
bool mumps_available();
/// Whether this build has the solver `kind`.
bool linear_solver_available(LinearSolverKind kind);
/// The fastest solver this build has (docs/quasi-static.md): MUMPS, else UMFPACK, else SparseLU.
LinearSolverKind default_linear_solver();
/// "sparse-lu", "umfpack", "mumps" (the names of `[solver] linear_solver`).
std::string to_string(LinearSolverKind kind);
/// The kind of one of those names; none for any other.
std::optional<LinearSolverKind> linear_solver_from_string(std::string_view name);
/// Throws InvalidValue (key "linear_solver", naming the default) for a kind this build lacks.
void require_linear_solver(LinearSolverKind kind);

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

class LinearSolver {
 public:
  LinearSolver();
  ~LinearSolver();
  LinearSolver(LinearSolver&&) noexcept;
  LinearSolver& operator=(LinearSolver&&) noexcept;

  /// Throws InvalidValue for a solver this build does not have.
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
