#include "core/spd_solver.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>

#include "core/stopwatch.hpp"

namespace c2d::core {

namespace {

/// Eigen's CHOLMOD wrapper plus the reciprocal condition estimate CHOLMOD computes from its
/// factor's diagonal ((min L_ii / max L_ii)^2 for LLᵀ).
class Cholmod : public Eigen::CholmodDecomposition<SpMat, Eigen::Lower> {
 public:
  bool is_supernodal() const { return m_cholmodFactor && m_cholmodFactor->is_super; }
  double rcond() {
    return m_cholmodFactor ? cholmod_rcond(m_cholmodFactor, &cholmod()) : 0.0;
  }
  /// Eigen's analyzePattern with a given elimination order (CHOLMOD's analysis then computes
  /// the elimination tree, its postorder and the supernodes, but no ordering of its own).
  void analyzePattern(const SpMat& matrix, const std::vector<int>& order) {
    if (order.empty()) return Base::analyzePattern(matrix);
    if (m_cholmodFactor) cholmod_free_factor(&m_cholmodFactor, &cholmod());
    cholmod_sparse a = Eigen::viewAsCholmod(matrix.selfadjointView<Eigen::Lower>());
    const int method = cholmod().method[0].ordering;
    cholmod().method[0].ordering = CHOLMOD_GIVEN;
    m_cholmodFactor = cholmod_analyze_p(&a, const_cast<int*>(order.data()), nullptr, 0, &cholmod());
    cholmod().method[0].ordering = method;
    m_isInitialized = true;
    m_info = m_cholmodFactor ? Eigen::Success : Eigen::NumericalIssue;
    m_analysisIsOk = m_cholmodFactor != nullptr;
    m_factorizationIsOk = false;
  }

 private:
  using Base = Eigen::CholmodDecomposition<SpMat, Eigen::Lower>;
};

/// Below this pivot ratio the matrix is singular to working precision (a rigid-body mode left
/// by missing supports gives pivots of round-off size, ~1e-16 of the largest).
constexpr double kSingularPivotRatio = 1e-14;

}  // namespace

struct SpdSolver::Impl {
  Backend preferred;
  Backend active;
  bool fallback = true;
  Cholmod cholmod;
  Eigen::SimplicialLDLT<SpMat, Eigen::Lower> ldlt;
  Eigen::Index analysed_rows = -1, analysed_nnz = -1;
  const SpMat* matrix = nullptr;
  std::vector<int> order;  ///< the caller's elimination order, empty for CHOLMOD's AMD
  std::string order_name;
};

SpdSolver::SpdSolver(Backend preferred, bool fallback) : impl_(std::make_unique<Impl>()) {
  impl_->preferred = preferred;
  impl_->fallback = fallback;
  impl_->active = preferred;
  impl_->cholmod.setMode(Eigen::CholmodAuto);
  // A failed factorisation is reported through info() and the solver report (and may fall back
  // to LDLT); CHOLMOD's own "not positive definite" warning on stderr would only duplicate it.
  impl_->cholmod.cholmod().print = 0;
  // One ordering, AMD. CHOLMOD's default also tries METIS when AMD's fill looks high, which on
  // 2D meshes of about 1M DOFs doubled the analysis for a factorisation no faster overall
  // (c2d_micro_bench, T6 grid, 982,802 DOFs: AMD 1.5 s + 9.2 s numeric; METIS 8.4 s + 8.2 s;
  // default 9.7 s + 10.3 s).
  auto& c = impl_->cholmod.cholmod();
  c.nmethods = 1;
  c.method[0].ordering = CHOLMOD_AMD;
  c.postorder = 1;
}

SpdSolver::~SpdSolver() = default;

void SpdSolver::set_ordering(std::vector<int> order, std::string name) {
  impl_->order = std::move(order);
  impl_->order_name = std::move(name);
  reset_pattern();
}

void SpdSolver::reset_pattern() {
  impl_->analysed_rows = -1;
  impl_->analysed_nnz = -1;
}

SolveStatus SpdSolver::factorize(const SpMat& k) {
  Impl& m = *impl_;
  m.matrix = &k;
  report_.message.clear();
  if (k.rows() == 0) {
    report_.status = SolveStatus::kConverged;
    return report_.status;
  }
  // Infinite or NaN entries would reach CHOLMOD as "not positive definite" and read as missing
  // supports; they come from overflowing data (material constants, coordinates, penalties).
  if (!k.coeffs().allFinite()) {
    report_.status = SolveStatus::kFailed;
    report_.message = "the stiffness matrix has non-finite entries (material constants, "
                      "coordinates or penalties overflow double precision)";
    return report_.status;
  }
  const bool same_pattern = m.analysed_rows == k.rows() && m.analysed_nnz == k.nonZeros();
  auto try_backend = [&](Backend b) -> bool {
    Stopwatch clock;
    if (b == Backend::kCholmod) {
      report_.backend = "cholmod";
      const bool given = static_cast<Eigen::Index>(m.order.size()) == k.rows();
      if (!same_pattern || m.active != b) {
        m.cholmod.analyzePattern(k, given ? m.order : std::vector<int>{});
        report_.symbolic_analyses++;
        report_.symbolic_seconds += clock.lap();
      }
      m.cholmod.factorize(k);
      report_.numeric_factorizations++;
      report_.numeric_seconds += clock.lap();
      const cholmod_common& c = m.cholmod.cholmod();
      static const char* const kOrderings[] = {"natural", "given", "amd", "metis", "nesdis", "colamd", "postordered"};
      const int o = c.method[c.selected].ordering;
      report_.ordering = given ? m.order_name : o >= 0 && o <= 6 ? kOrderings[o] : "unknown";
      report_.supernodal = m.cholmod.is_supernodal();
      report_.factor_nonzeros = c.lnz;
      return m.cholmod.info() == Eigen::Success;
    }
    report_.backend = "eigen_ldlt";
    if (!same_pattern || m.active != b) {
      m.ldlt.analyzePattern(k);
      report_.symbolic_analyses++;
      report_.symbolic_seconds += clock.lap();
    }
    m.ldlt.factorize(k);
    report_.numeric_factorizations++;
    report_.numeric_seconds += clock.lap();
    report_.ordering = "amd";
    report_.supernodal = false;
    if (m.ldlt.info() != Eigen::Success) return false;
    const VecX d = m.ldlt.vectorD();
    return d.minCoeff() > 0.0 && std::isfinite(d.sum());
  };
  bool ok = try_backend(m.preferred);
  m.active = m.preferred;
  if (!ok && m.preferred == Backend::kCholmod && m.fallback) {
    // CHOLMOD stops at the first non-positive pivot; LDLT tells us the pivots, so a singular or
    // indefinite matrix is named rather than guessed.
    ok = try_backend(Backend::kEigenLdlt);
    m.active = Backend::kEigenLdlt;
  }
  m.analysed_rows = k.rows();
  m.analysed_nnz = k.nonZeros();
  if (m.active == Backend::kEigenLdlt) {
    const VecX d = m.ldlt.vectorD();
    const double dmax = d.cwiseAbs().maxCoeff(), dmin = d.cwiseAbs().minCoeff();
    report_.pivot_ratio = dmax > 0 ? dmin / dmax : 0.0;
  } else if (ok) {
    report_.pivot_ratio = m.cholmod.rcond();
  }
  if (ok && report_.pivot_ratio < kSingularPivotRatio) ok = false;
  if (!ok) {
    report_.status = SolveStatus::kSingular;
    report_.message = "stiffness matrix is singular or not positive definite (a body free to "
                      "move as a rigid body? missing supports?)";
    return report_.status;
  }
  report_.status = SolveStatus::kConverged;
  return report_.status;
}

SolveStatus SpdSolver::solve(const VecX& b, VecX& x) {
  Impl& m = *impl_;
  if (b.size() == 0) {
    x.resize(0);
    return SolveStatus::kConverged;
  }
  if (report_.status != SolveStatus::kConverged) return report_.status;
  const Stopwatch clock;
  x = m.active == Backend::kCholmod ? VecX(m.cholmod.solve(b)) : VecX(m.ldlt.solve(b));
  const double bn = b.norm();
  const VecX r = (*m.matrix).selfadjointView<Eigen::Lower>() * x - b;
  report_.relative_residual = bn > 0 ? r.norm() / bn : r.norm();
  report_.solve_seconds += clock.elapsed();
  if (!x.allFinite() || !std::isfinite(report_.relative_residual)) {
    report_.status = SolveStatus::kSingular;
    report_.message = "solution is not finite (singular stiffness matrix)";
  } else if (report_.relative_residual > 1e-6) {
    report_.status = SolveStatus::kIllConditioned;
    report_.message = "relative residual " + std::to_string(report_.relative_residual) +
                      " after the direct solve (ill-conditioned stiffness matrix)";
  }
  return report_.status;
}

SolveStatus SpdSolver::solve(const Eigen::MatrixXd& b, Eigen::MatrixXd& x) {
  Impl& m = *impl_;
  if (b.size() == 0) {
    x.resize(b.rows(), b.cols());
    return SolveStatus::kConverged;
  }
  if (report_.status != SolveStatus::kConverged) return report_.status;
  const Stopwatch clock;
  x = m.active == Backend::kCholmod ? Eigen::MatrixXd(m.cholmod.solve(b))
                                    : Eigen::MatrixXd(m.ldlt.solve(b));
  // The residual of a fixed combination of the columns, K (X w) − B w: one product instead of
  // one per column (which cost more than the solve itself for a hundred columns). A column
  // solved badly shows in the combination unless its error cancels exactly against another's.
  VecX w(b.cols());
  for (Eigen::Index c = 0; c < b.cols(); ++c) w[c] = 1.0 + 0.618033988749895 * static_cast<double>(c % 7);
  const VecX bw = b * w;
  const VecX r = (*m.matrix).selfadjointView<Eigen::Lower>() * VecX(x * w) - bw;
  const double bn = bw.norm();
  const double worst = bn > 0 ? r.norm() / bn : r.norm();
  report_.relative_residual = worst;
  report_.solve_seconds += clock.elapsed();
  if (!x.allFinite() || !std::isfinite(worst)) {
    report_.status = SolveStatus::kSingular;
    report_.message = "solution is not finite (singular stiffness matrix)";
  } else if (worst > 1e-6) {
    report_.status = SolveStatus::kIllConditioned;
    report_.message = "relative residual " + std::to_string(worst) +
                      " after the direct solve (ill-conditioned stiffness matrix)";
  }
  return report_.status;
}

}  // namespace c2d::core
