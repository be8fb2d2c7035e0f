#include "pilempm/mpm/quasi_static/linear_solver.hpp"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseLU>
#ifdef PILEMPM_HAVE_UMFPACK
#include <Eigen/UmfPackSupport>
#endif

#include "pilempm/core/error.hpp"

namespace pilempm::mpm::quasi_static {

bool umfpack_available() {
#ifdef PILEMPM_HAVE_UMFPACK
  return true;
#else
  return false;
#endif
}

std::string to_string(LinearSolverKind kind) {
  return kind == LinearSolverKind::umfpack ? "umfpack" : "sparse-lu";
}

struct LinearSolver::Backend {
  Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>> sparse_lu;
#ifdef PILEMPM_HAVE_UMFPACK
  Eigen::UmfPackLU<SparseMatrix> umfpack;
#endif
};

LinearSolver::LinearSolver() : backend_(std::make_unique<Backend>()) {}
LinearSolver::~LinearSolver() = default;
LinearSolver::LinearSolver(LinearSolver&&) noexcept = default;
LinearSolver& LinearSolver::operator=(LinearSolver&&) noexcept = default;

void LinearSolver::set_kind(LinearSolverKind kind) {
  if (kind == LinearSolverKind::umfpack && !umfpack_available())
    throw InvalidValue("linear solver", "umfpack", "sparse-lu (this build has no UMFPACK)");
  kind_ = kind;
}

bool LinearSolver::factorize(const SparseMatrix& matrix, bool new_pattern) {
#ifdef PILEMPM_HAVE_UMFPACK
  if (kind_ == LinearSolverKind::umfpack) {
    // UMFPACK's symbolic analysis depends on the pattern only; the numeric one on the values.
    if (new_pattern) backend_->umfpack.analyzePattern(matrix);
    backend_->umfpack.factorize(matrix);
    return backend_->umfpack.info() == Eigen::Success;
  }
#endif
  if (new_pattern) backend_->sparse_lu.analyzePattern(matrix);
  backend_->sparse_lu.factorize(matrix);
  return backend_->sparse_lu.info() == Eigen::Success;
}

Eigen::VectorXd LinearSolver::solve(const Eigen::VectorXd& b) const {
#ifdef PILEMPM_HAVE_UMFPACK
  if (kind_ == LinearSolverKind::umfpack) return backend_->umfpack.solve(b);
#endif
  return backend_->sparse_lu.solve(b);
}

}  // namespace pilempm::mpm::quasi_static
