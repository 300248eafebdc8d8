#include "constraints/kkt_solver.hpp"

#include "core/errors.hpp"
#include "core/stopwatch.hpp"

#include <Eigen/UmfPackSupport>
#include <cmath>
#include <cstdio>

namespace c2d::constraints {



namespace {
// Eigen keeps UMFPACK's statistics protected; the condition estimate is in them.
class UmfLu : public Eigen::UmfPackLU<SpMat> {
 public:
  double rcond() const { return m_umfpackInfo[UMFPACK_RCOND]; }
};
}  // namespace

struct KktSolver::Impl {
  UmfLu lu;
  SpMat matrix;
  bool analysed = false;
};

KktSolver::KktSolver() : impl_(std::make_unique<Impl>()) {}
KktSolver::~KktSolver() = default;

SolveStatus KktSolver::factorize(const SpMat& m, bool same_pattern) {
  impl_->matrix = m;
  impl_->matrix.makeCompressed();
  core::Stopwatch clock;
  if (!same_pattern || !impl_->analysed) {
    impl_->lu.analyzePattern(impl_->matrix);
    ++report_.symbolic_analyses;
    report_.symbolic_seconds += clock.lap();
    if (impl_->lu.info() != Eigen::Success) {
      impl_->analysed = false;
      report_.status = SolveStatus::kFailed;
      report_.message = "UMFPACK symbolic analysis failed";
      return report_.status;
    }
    impl_->analysed = true;
  }
  impl_->lu.factorize(impl_->matrix);
  ++report_.numeric_factorizations;
  report_.numeric_seconds += clock.lap();
  report_.rcond = impl_->lu.rcond();
  if (impl_->lu.info() != Eigen::Success || !(report_.rcond > 1e-15)) {
    report_.status = SolveStatus::kSingular;
    char rcond[32];
    std::snprintf(rcond, sizeof rcond, "%.3g", report_.rcond);
    report_.message = std::string("saddle-point matrix is singular (UMFPACK rcond ") + rcond +
                      "): linearly dependent constraint rows or an unsupported body";
    return report_.status;
  }
  report_.status = SolveStatus::kConverged;
  report_.message.clear();
  return report_.status;
}

SolveStatus KktSolver::solve(const VecX& b, VecX& x) {
  if (report_.status != SolveStatus::kConverged) return report_.status;
  core::Stopwatch clock;
  x = impl_->lu.solve(b);
  const double bn = b.norm();
  report_.relative_residual = (impl_->matrix * x - b).norm() / (bn > 0 ? bn : 1.0);
  report_.solve_seconds += clock.lap();
  if (impl_->lu.info() != Eigen::Success || !x.allFinite()) {
    report_.status = SolveStatus::kFailed;
    report_.message = "UMFPACK solve failed";
    x.setZero(b.size());
  } else if (!(report_.relative_residual < 1.0)) {
    // Not one digit: the factorisation passed its pivot test, but the matrix is singular to
    // working precision (a body free to turn about the few rows that hold it).
    report_.status = SolveStatus::kSingular;
    report_.message = "saddle-point matrix is singular to working precision (solve residual " +
                      number_text(report_.relative_residual) +
                      "): linearly dependent constraint rows or an unsupported body";
  } else if (report_.relative_residual > 1e-6) {
    report_.status = SolveStatus::kIllConditioned;
    report_.message = "saddle-point solve residual " + number_text(report_.relative_residual);
  }
  return report_.status;
}

}  // namespace c2d::constraints
