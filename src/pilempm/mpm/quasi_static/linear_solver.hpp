#pragma once
// The sparse direct solver of the quasi-static analysis: LU of a general (unsymmetric) sparse
// matrix, from MUMPS (sequential, multifrontal, AMD ordering; in single precision with iterative
// refinement to a double-precision residual, or in double precision) or SuiteSparse UMFPACK
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
  mumps,      ///< MUMPS, sequential, double precision (only where built with it)
  /// MUMPS, sequential: the LU in single precision, each solution refined in double precision
  /// until its residual is below kRefinementTolerance of the right-hand side, the LU redone in
  /// double precision where the refinement does not get there (only where built with MUMPS)
  mumps_mixed,
};
/// Every kind, fastest first (the order of default_linear_solver's choice).
inline constexpr std::array<LinearSolverKind, 4> kLinearSolverKinds = {
    LinearSolverKind::mumps_mixed, LinearSolverKind::mumps, LinearSolverKind::umfpack,
    LinearSolverKind::sparse_lu};

/// `mumps_mixed`: a solution is refined until ||b - A x|| <= this * ||b|| (or, for a nearly
/// singular matrix, to the backward error of a double-precision LU, √n ε ||A||_F ||x||). Newton's
/// method needs its step far less exactly (an inexact Newton step of relative residual η changes
/// the next residual by η of this one); 10⁻¹⁰ keeps the steps those of an exact solver for any
/// tolerance a case may ask (docs/quasi-static.md, "Sparse direct solver").
inline constexpr double kRefinementTolerance = 1.0e-10;
/// `mumps_mixed`: at most this many single-precision solves per right-hand side (the first and
/// the refinements) before the LU is redone in double precision.
inline constexpr int kMaxRefinementSolves = 6;

/// What a LinearSolver has done since it was made.
struct LinearSolverCounts {
  long factorisations = 0;    ///< factorize calls that succeeded
  long solves = 0;            ///< solve calls
  long precision_solves = 0;  ///< mumps_mixed: single-precision solves (first and refinements)
  long double_fallbacks = 0;  ///< mumps_mixed: LUs redone in double precision
};
/// Whether this build has UMFPACK.
bool umfpack_available();
/// Whether this build has MUMPS.
bool mumps_available();
/// Whether this build has the solver `kind`.
bool linear_solver_available(LinearSolverKind kind);
/// The fastest solver this build has (docs/quasi-static.md): MUMPS in mixed precision, else
/// UMFPACK, else SparseLU.
LinearSolverKind default_linear_solver();
/// "sparse-lu", "umfpack", "mumps", "mumps-mixed" (the names of `[solver] linear_solver`).
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
  const LinearSolverCounts& counts() const;

 private:
  bool factorize_with_backend(const SparseMatrix& matrix, bool new_pattern);
  struct Backend;
  LinearSolverKind kind_ = LinearSolverKind::sparse_lu;
  std::unique_ptr<Backend> backend_;
};

}  // namespace pilempm::mpm::quasi_static
