#include "core/spd_solver.hpp"

#include <omp.h>

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>

#include "core/errors.hpp"
#include "core/factor_blocks.hpp"
#include "core/sparse_pattern.hpp"
#include "core/split_cholesky.hpp"
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
  AnalysedPattern analysed;  ///< the pattern the active backend analysed
  const SpMat* matrix = nullptr;
  std::shared_ptr<const FillOrder> fill;  ///< the caller's elimination order, null for AMD
  std::string order_name;
  SplitCholesky split;
  bool use_split = false;  ///< the analysed pattern factorises split in two halves
  int threads = 1;

  bool given(const SpMat& k) const {
    return fill && static_cast<Eigen::Index>(fill->order.size()) == k.rows();
  }
  /// The analysis of K's pattern: split when the fill order carries a split that applies, else
  /// CHOLMOD's. The split does not depend on the threads (one thread runs the halves one after
  /// the other, as fast as one factorisation of the whole), so neither do the numbers.
  void analyse(const SpMat& k) {
    threads = omp_get_max_threads();
    use_split = given(k) && static_cast<Eigen::Index>(fill->part.size()) == k.rows() &&
                split.analyse(k, fill->order, fill->part, threads);
    if (!use_split) cholmod.analyzePattern(k, given(k) ? fill->order : std::vector<int>{});
  }

  /// CHOLMOD's factorisation, split or whole, analysing first if asked; false when K is not
  /// positive definite.
  bool factorize_cholmod(const SpMat& k, bool analyse_pattern, SpdSolveReport& r) {
    Stopwatch clock;
    r.backend = "cholmod";
    if (analyse_pattern) {
      analyse(k);
      r.symbolic_analyses++;
      r.symbolic_seconds += clock.lap();
    }
    r.numeric_factorizations++;
    if (use_split) {
      const SolveStatus st = split.factorize(k, threads);
      r.numeric_seconds += clock.lap();
      r.ordering = order_name + "_split";
      r.supernodal = true;
      r.factor_nonzeros = split.factor_nonzeros();
      r.separator = split.separator_size();
      return st == SolveStatus::kConverged;
    }
    {
      // CHOLMOD's own four-thread regions stay within a one-thread budget (ActiveLevelCap).
      const ActiveLevelCap cap(threads > 1 ? 1 : 0);
      cholmod.factorize(k);
    }
    r.numeric_seconds += clock.lap();
    const cholmod_common& c = cholmod.cholmod();
    static const char* const kOrderings[] = {"natural", "given", "amd", "metis", "nesdis", "colamd", "postordered"};
    const int o = c.method[c.selected].ordering;
    r.ordering = given(k) ? order_name : o >= 0 && o <= 6 ? kOrderings[o] : "unknown";
    r.supernodal = cholmod.is_supernodal();
    r.factor_nonzeros = c.lnz;
    r.separator = 0;
    return cholmod.info() == Eigen::Success;
  }

  /// Eigen's LDLT, analysing first if asked; false unless every pivot is positive and finite.
  bool factorize_ldlt(const SpMat& k, bool analyse_pattern, SpdSolveReport& r) {
    Stopwatch clock;
    r.backend = "eigen_ldlt";
    if (analyse_pattern) {
      ldlt.analyzePattern(k);
      r.symbolic_analyses++;
      r.symbolic_seconds += clock.lap();
    }
    ldlt.factorize(k);
    r.numeric_factorizations++;
    r.numeric_seconds += clock.lap();
    r.ordering = "amd";
    r.supernodal = false;
    r.separator = 0;
    if (ldlt.info() != Eigen::Success) return false;
    const VecX d = ldlt.vectorD();
    return d.minCoeff() > 0.0 && std::isfinite(d.sum());
  }
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

void SpdSolver::set_ordering(std::shared_ptr<const FillOrder> fill, std::string name) {
  impl_->fill = std::move(fill);
  impl_->order_name = std::move(name);
  reset_pattern();
}

void SpdSolver::reset_pattern() {
  impl_->analysed.clear();
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
  const bool same_pattern = m.analysed.matches(k);
  auto try_backend = [&](Backend b) {
    const bool analyse = !same_pattern || m.active != b;
    return b == Backend::kCholmod ? m.factorize_cholmod(k, analyse, report_)
                                  : m.factorize_ldlt(k, analyse, report_);
  };
  bool ok = try_backend(m.preferred);
  m.active = m.preferred;
  if (!ok && m.preferred == Backend::kCholmod && m.fallback) {
    // CHOLMOD stops at the first non-positive pivot; LDLT tells us the pivots, so a singular or
    // indefinite matrix is named rather than guessed.
    ok = try_backend(Backend::kEigenLdlt);
    m.active = Backend::kEigenLdlt;
  }
  m.analysed.keep(k);
  if (m.active == Backend::kEigenLdlt) {
    const VecX d = m.ldlt.vectorD();
    const double dmax = d.cwiseAbs().maxCoeff(), dmin = d.cwiseAbs().minCoeff();
    report_.pivot_ratio = dmax > 0 ? dmin / dmax : 0.0;
  } else if (ok) {
    report_.pivot_ratio = m.use_split ? m.split.pivot_ratio() : m.cholmod.rcond();
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
  if (m.active == Backend::kCholmod && m.use_split) {
    Eigen::MatrixXd xm;
    if (m.split.solve(b, xm, m.threads) != SolveStatus::kConverged) xm.setConstant(b.size(), 1, NAN);
    x = xm.col(0);
  } else {
    x = m.active == Backend::kCholmod ? VecX(m.cholmod.solve(b)) : VecX(m.ldlt.solve(b));
  }
  const double bn = b.norm();
  const VecX r = (*m.matrix).selfadjointView<Eigen::Lower>() * x - b;
  report_.relative_residual = bn > 0 ? r.norm() / bn : r.norm();
  report_.solve_seconds += clock.elapsed();
  if (!x.allFinite() || !std::isfinite(report_.relative_residual)) {
    report_.status = SolveStatus::kSingular;
    report_.message = "solution is not finite (singular stiffness matrix)";
  } else if (report_.relative_residual > 1e-6) {
    report_.status = SolveStatus::kIllConditioned;
    report_.message = "relative residual " + number_text(report_.relative_residual) +
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
  if (m.active == Backend::kCholmod && m.use_split) {
    if (m.split.solve(b, x, m.threads) != SolveStatus::kConverged) x.setConstant(b.rows(), b.cols(), NAN);
  } else {
    x = m.active == Backend::kCholmod ? Eigen::MatrixXd(m.cholmod.solve(b))
                                      : Eigen::MatrixXd(m.ldlt.solve(b));
  }
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
    report_.message = "relative residual " + number_text(worst) +
                      " after the direct solve (ill-conditioned stiffness matrix)";
  }
  return report_.status;
}

}  // namespace c2d::core
