#include "pilempm/mpm/quasi_static/linear_solver.hpp"

#include <dlfcn.h>
#include <fmt/format.h>

#include <Eigen/OrderingMethods>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>
#ifdef PILEMPM_HAVE_UMFPACK
#include <Eigen/UmfPackSupport>
#endif
#ifdef PILEMPM_HAVE_MUMPS
#include <dmumps_c.h>
#include <smumps_c.h>
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
    case LinearSolverKind::mumps_mixed:
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
    case LinearSolverKind::mumps_mixed:
      return "mumps-mixed";
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
// factorisation (job 2) per matrix, solution (job 3) per right-hand side. `Struct`, `Real` and
// `call` pick the arithmetic: DMUMPS (double) or SMUMPS (single precision).
template <class Struct, class Real, void (*call)(Struct*)>
class Mumps {
 public:
  Mumps() {
    id_.comm_fortran = kUseCommWorld;
    id_.par = 1;  // the host works (sequential library)
    id_.sym = 0;  // unsymmetric
    id_.job = kInitialise;
    call(&id_);
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
    call(&id_);
  }
  Mumps(const Mumps&) = delete;
  Mumps& operator=(const Mumps&) = delete;

  /// The pattern is analysed when `new_pattern` or when the last analysis failed.
  bool factorize(const SparseMatrix& matrix, bool new_pattern) {
    if (matrix.rows() == 0) return true;
    const auto entries = std::size_t(matrix.nonZeros());
    values_.resize(entries);
    std::transform(matrix.valuePtr(), matrix.valuePtr() + entries, values_.begin(),
                   [](double v) { return Real(v); });
    id_.a = values_.data();
    if (new_pattern || !analysed_) {
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
      call(&id_);
      analysed_ = id_.infog[0] >= 0;
      if (!analysed_) return false;
    }
    // Too little workspace for the pivots' delays (INFOG(1) = -8, -9): more, and again.
    id_.icntl[13] = kWorkspaceRelaxation;
    for (int attempt = 0; attempt < 4; ++attempt) {
      id_.job = kFactorise;
      call(&id_);
      if (id_.infog[0] != -8 && id_.infog[0] != -9) break;
      id_.icntl[13] *= 2;
    }
    return id_.infog[0] >= 0;
  }

  /// Overwrites `x` (as many values as the matrix has rows) with A⁻¹ x.
  void solve(Real* x) {
    id_.rhs = x;
    id_.nrhs = 1;
    id_.lrhs = id_.n;
    id_.job = kSolve;
    call(&id_);
  }

  Eigen::VectorXd solve(const Eigen::VectorXd& b) {
    std::vector<Real> x(b.data(), b.data() + b.size());
    if (!x.empty()) solve(x.data());
    return Eigen::Map<const Eigen::Matrix<Real, Eigen::Dynamic, 1>>(x.data(), b.size())
        .template cast<double>();
  }

 private:
  static constexpr MUMPS_INT kUseCommWorld = -987654;
  static constexpr MUMPS_INT kInitialise = -1, kTerminate = -2, kAnalyse = 1, kFactorise = 2,
                             kSolve = 3;
  static constexpr MUMPS_INT kWorkspaceRelaxation = 20;  ///< ICNTL(14), MUMPS's default [%]
  Struct id_{};
  bool analysed_ = false;
  std::vector<MUMPS_INT> rows_, columns_;
  std::vector<Real> values_;
};

using DoubleMumps = Mumps<DMUMPS_STRUC_C, double, dmumps_c>;
using SingleMumps = Mumps<SMUMPS_STRUC_C, float, smumps_c>;

// Mixed precision (Buttari et al. 2007, ACM Trans. Math. Softw. 34(4); Carson & Higham 2018,
// SIAM J. Sci. Comput. 40(2)): the LU in single precision, which takes about 0.6 of the double
// one's time on the pile's Newton matrices and half its memory, and classic iterative
// refinement, x += LU⁻¹ (b − A x) with the residual in double precision, until
// ||b − A x|| <= kRefinementTolerance ||b||. The refinement's error falls by about
// cond(A) × 6e-8 a solve; where the matrix is too ill-conditioned for that (or the
// single-precision LU fails) the same matrix is factorised in double precision instead, and
// that LU serves the rest of its solves.
class MixedMumps {
 public:
  bool factorize(const SparseMatrix& matrix, bool new_pattern, LinearSolverCounts& counts) {
    matrix_ = matrix;
    matrix_norm_ = -1.0;  // taken when first needed
    if (new_pattern) double_analysed_ = false;
    single_usable_ = single_.factorize(matrix, new_pattern);
    if (single_usable_) return true;
    return factorize_double(counts);
  }

  Eigen::VectorXd solve(const Eigen::VectorXd& b, LinearSolverCounts& counts) {
    if (b.size() == 0) return b;
    if (single_usable_) {
      Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size());
      // The goal: the stated fraction of ||b||, or, where that is below what any LU in double
      // precision gives (a nearly singular matrix whose solution is large), a backward error of
      // √n ε ||A||_F ||x|| (Higham 2002 §9).
      const double wanted = kRefinementTolerance * b.norm();
      const auto reached = [&](double norm) {
        return norm <= wanted || norm <= double_precision_floor() * x.norm();
      };
      Eigen::VectorXd residual = b;
      double norm = b.norm(), last = std::numeric_limits<double>::infinity();
      std::vector<float> correction(std::size_t(b.size()));
      for (int solve = 0; solve < kMaxRefinementSolves && !reached(norm); ++solve) {
        if (!(norm < 0.5 * last)) break;  // not converging (or not finite)
        last = norm;
        for (std::size_t i = 0; i < correction.size(); ++i)
          correction[i] = float(residual[Eigen::Index(i)]);
        single_.solve(correction.data());
        ++counts.precision_solves;
        for (std::size_t i = 0; i < correction.size(); ++i)
          x[Eigen::Index(i)] += double(correction[i]);
        residual.noalias() = b - matrix_ * x;
        norm = residual.norm();
      }
      if (reached(norm)) return x;
      single_usable_ = false;
      if (!factorize_double(counts)) return Eigen::VectorXd::Constant(b.size(), kNaN);
    }
    return double_.solve(b);
  }

 private:
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

  // √n ε ||A||_F of the factorised matrix; its norm is taken once, and only for a solve that
  // has not reached kRefinementTolerance ||b||.
  double double_precision_floor() {
    if (matrix_norm_ < 0.0) matrix_norm_ = matrix_.norm();
    return std::sqrt(double(matrix_.rows())) * std::numeric_limits<double>::epsilon() *
           matrix_norm_;
  }

  bool factorize_double(LinearSolverCounts& counts) {
    ++counts.double_fallbacks;
    const bool ok = double_.factorize(matrix_, !double_analysed_);
    double_analysed_ = ok;
    return ok;
  }

  SingleMumps single_;
  DoubleMumps double_;         // the fallback; analysed when first needed for a pattern
  SparseMatrix matrix_;        // the factorised matrix: the refinement's residuals
  double matrix_norm_ = -1.0;  // its Frobenius norm; < 0: not yet taken
  bool single_usable_ = false, double_analysed_ = false;
};

}  // namespace
#endif

struct LinearSolver::Backend {
  Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>> sparse_lu;
#ifdef PILEMPM_HAVE_UMFPACK
  Eigen::UmfPackLU<SparseMatrix> umfpack;
#endif
#ifdef PILEMPM_HAVE_MUMPS
  std::unique_ptr<DoubleMumps> mumps;  // made when first used
  std::unique_ptr<MixedMumps> mixed;
#endif
  LinearSolverCounts counts;
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
  const bool ok = factorize_with_backend(matrix, new_pattern);
  if (ok) ++backend_->counts.factorisations;
  return ok;
}

bool LinearSolver::factorize_with_backend(const SparseMatrix& matrix, bool new_pattern) {
#ifdef PILEMPM_HAVE_MUMPS
  if (kind_ == LinearSolverKind::mumps) {
    if (!backend_->mumps) {
      backend_->mumps = std::make_unique<DoubleMumps>();
      new_pattern = true;
    }
    return backend_->mumps->factorize(matrix, new_pattern);
  }
  if (kind_ == LinearSolverKind::mumps_mixed) {
    if (!backend_->mixed) {
      backend_->mixed = std::make_unique<MixedMumps>();
      new_pattern = true;
    }
    return backend_->mixed->factorize(matrix, new_pattern, backend_->counts);
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

const LinearSolverCounts& LinearSolver::counts() const {
  return backend_->counts;
}

Eigen::VectorXd LinearSolver::solve(const Eigen::VectorXd& b) const {
  ++backend_->counts.solves;
#ifdef PILEMPM_HAVE_MUMPS
  if (kind_ == LinearSolverKind::mumps) return backend_->mumps->solve(b);
  if (kind_ == LinearSolverKind::mumps_mixed) return backend_->mixed->solve(b, backend_->counts);
#endif
#ifdef PILEMPM_HAVE_UMFPACK
  if (kind_ == LinearSolverKind::umfpack) return backend_->umfpack.solve(b);
#endif
  return backend_->sparse_lu.solve(b);
}

}  // namespace pilempm::mpm::quasi_static
