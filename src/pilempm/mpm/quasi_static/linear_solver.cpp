#include "pilempm/mpm/quasi_static/linear_solver.hpp"

#include <dlfcn.h>
#include <fmt/format.h>

#include <Eigen/OrderingMethods>
#include <Eigen/SparseLU>
#include <cstring>
#include <vector>
#ifdef PILEMPM_HAVE_UMFPACK
#include <Eigen/UmfPackSupport>
#endif
#ifdef PILEMPM_HAVE_MUMPS
#include <dmumps_c.h>
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

bool mumps_available() {
#ifdef PILEMPM_HAVE_MUMPS
  return true;
#else
  return false;
#endif
}

bool linear_solver_available(LinearSolverKind kind) {
  switch (kind) {
    case LinearSolverKind::umfpack:
      return umfpack_available();
    case LinearSolverKind::mumps:
      return mumps_available();
    case LinearSolverKind::sparse_lu:
      break;
  }
  return true;
}

LinearSolverKind default_linear_solver() {
  for (const LinearSolverKind kind : kLinearSolverKinds)
    if (linear_solver_available(kind)) return kind;
  return LinearSolverKind::sparse_lu;
}

std::string to_string(LinearSolverKind kind) {
  switch (kind) {
    case LinearSolverKind::umfpack:
      return "umfpack";
    case LinearSolverKind::mumps:
      return "mumps";
    case LinearSolverKind::sparse_lu:
      break;
  }
  return "sparse-lu";
}

std::optional<LinearSolverKind> linear_solver_from_string(std::string_view name) {
  for (const LinearSolverKind kind : kLinearSolverKinds)
    if (to_string(kind) == name) return kind;
  return std::nullopt;
}

void require_linear_solver(LinearSolverKind kind) {
  if (!linear_solver_available(kind))
    throw InvalidValue("linear_solver", to_string(kind),
                       fmt::format("{} (this build has no {})", to_string(default_linear_solver()),
                                   to_string(kind)));
}

#ifdef PILEMPM_HAVE_MUMPS
namespace {

// MUMPS 5 (Amestoy et al. 2001, SIAM J. Matrix Anal. Appl. 23(1)), sequential, through its C
// interface: the matrix in coordinates (1-based), analysis (job 1) once per pattern,
// factorisation (job 2) per matrix, solution (job 3) per right-hand side.
class Mumps {
 public:
  Mumps() {
    id_.comm_fortran = kUseCommWorld;
    id_.par = 1;  // the host works (sequential library)
    id_.sym = 0;  // unsymmetric
    id_.job = kInitialise;
    dmumps_c(&id_);
    id_.icntl[0] = -1;  // ICNTL(1-4): no messages
    id_.icntl[1] = -1;
    id_.icntl[2] = -1;
    id_.icntl[3] = 0;
    id_.icntl[6] = 0;  // ICNTL(7): AMD ordering, the fastest of MUMPS's on the pile's matrices
    // ICNTL(8): no scaling. MUMPS's automatic choice scales rows and columns iteratively at
    // every factorisation (simultaneous scaling, 12-25 % of the factorisation's time on the
    // pile's matrices); the threshold pivoting keeps the LU stable without it, and MPM-2 took
    // 3 099 Newton iterations without against 3 160 with it (docs/quasi-static.md).
    id_.icntl[7] = 0;
  }
  ~Mumps() {
    id_.job = kTerminate;
    dmumps_c(&id_);
  }
  Mumps(const Mumps&) = delete;
  Mumps& operator=(const Mumps&) = delete;

  bool factorize(const SparseMatrix& matrix, bool new_pattern) {
    if (matrix.rows() == 0) return true;
    const auto entries = std::size_t(matrix.nonZeros());
    values_.assign(matrix.valuePtr(), matrix.valuePtr() + entries);
    id_.a = values_.data();
    if (new_pattern) {
      rows_.resize(entries);
      columns_.resize(entries);
      for (int c = 0; c < matrix.outerSize(); ++c)
        for (int k = matrix.outerIndexPtr()[c]; k < matrix.outerIndexPtr()[c + 1]; ++k) {
          rows_[std::size_t(k)] = matrix.innerIndexPtr()[k] + 1;
          columns_[std::size_t(k)] = c + 1;
        }
      id_.n = MUMPS_INT(matrix.rows());
      id_.nnz = MUMPS_INT8(entries);
      id_.irn = rows_.data();
      id_.jcn = columns_.data();
      id_.job = kAnalyse;
      dmumps_c(&id_);
      if (id_.infog[0] < 0) return false;
    }
    // Too little workspace for the pivots' delays (INFOG(1) = -8, -9): more, and again.
    id_.icntl[13] = kWorkspaceRelaxation;
    for (int attempt = 0; attempt < 4; ++attempt) {
      id_.job = kFactorise;
      dmumps_c(&id_);
      if (id_.infog[0] != -8 && id_.infog[0] != -9) break;
      id_.icntl[13] *= 2;
    }
    return id_.infog[0] >= 0;
  }

  Eigen::VectorXd solve(const Eigen::VectorXd& b) {
    Eigen::VectorXd x = b;
    if (x.size() == 0) return x;
    id_.rhs = x.data();
    id_.nrhs = 1;
    id_.lrhs = id_.n;
    id_.job = kSolve;
    dmumps_c(&id_);
    return x;
  }

 private:
  static constexpr MUMPS_INT kUseCommWorld = -987654;
  static constexpr MUMPS_INT kInitialise = -1, kTerminate = -2, kAnalyse = 1, kFactorise = 2,
                             kSolve = 3;
  static constexpr MUMPS_INT kWorkspaceRelaxation = 20;  ///< ICNTL(14), MUMPS's default [%]
  DMUMPS_STRUC_C id_{};
  std::vector<MUMPS_INT> rows_, columns_;
  std::vector<double> values_;
};

}  // namespace
#endif

struct LinearSolver::Backend {
  Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>> sparse_lu;
#ifdef PILEMPM_HAVE_UMFPACK
  Eigen::UmfPackLU<SparseMatrix> umfpack;
#endif
#ifdef PILEMPM_HAVE_MUMPS
  std::unique_ptr<Mumps> mumps;  // made when first used
#endif
};

namespace {

// OpenBLAS's pthreads build (Debian's libopenblas0-pthread, which `libopenblas0` and
// `libopenblas-dev` bring) keeps worker threads that wait for the next call by spinning on
// sched_yield; beside the analysis's OpenMP loops on a few cores they take a core's time (the
// quick case on 2 cores: 19 s of system time in a 36 s run, docs/benchmarks.md). The fronts of
// these matrices are small and two BLAS threads made no factorisation faster, so the BLAS under
// MUMPS and UMFPACK is told to use one thread where it is OpenBLAS (found at run time: the build
// may link any BLAS).
void use_one_blas_thread() {
  static const bool done = [] {
    void* symbol = dlsym(RTLD_DEFAULT, "openblas_set_num_threads");
    if (symbol != nullptr) {
      void (*set_threads)(int) = nullptr;
      std::memcpy(&set_threads, &symbol, sizeof set_threads);
      set_threads(1);
    }
    return true;
  }();
  (void)done;
}

}  // namespace

LinearSolver::LinearSolver() : backend_(std::make_unique<Backend>()) {
  use_one_blas_thread();
}
LinearSolver::~LinearSolver() = default;
LinearSolver::LinearSolver(LinearSolver&&) noexcept = default;
LinearSolver& LinearSolver::operator=(LinearSolver&&) noexcept = default;

void LinearSolver::set_kind(LinearSolverKind kind) {
  require_linear_solver(kind);
  kind_ = kind;
}

bool LinearSolver::factorize(const SparseMatrix& matrix, bool new_pattern) {
#ifdef PILEMPM_HAVE_MUMPS
  if (kind_ == LinearSolverKind::mumps) {
    if (!backend_->mumps) {
      backend_->mumps = std::make_unique<Mumps>();
      new_pattern = true;
    }
    return backend_->mumps->factorize(matrix, new_pattern);
  }
#endif
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
#ifdef PILEMPM_HAVE_MUMPS
  if (kind_ == LinearSolverKind::mumps) return backend_->mumps->solve(b);
#endif
#ifdef PILEMPM_HAVE_UMFPACK
  if (kind_ == LinearSolverKind::umfpack) return backend_->umfpack.solve(b);
#endif
  return backend_->sparse_lu.solve(b);
}

}  // namespace pilempm::mpm::quasi_static
