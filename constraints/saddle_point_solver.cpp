#include "constraints/saddle_point_solver.hpp"

#include <algorithm>
#include <cmath>

#include "constraints/strategy_common.hpp"
#include "constraints/surface_condensation.hpp"
#include "core/errors.hpp"
#include "core/stopwatch.hpp"

namespace c2d::constraints {

namespace {
/// Rows of the dense Schur complement (its LU costs k³/3 flops per active set: 0.3 GFlop here)
/// when its columns come from solves with K_ρ's factor (4·nnz(L) flops a row).
constexpr int kMaxSchurRows = 1000;
/// The same with K_ρ condensed onto the surface, whose columns are dense work on the tail:
/// up to 4,000 rows (21 GFlop an LU, k² doubles: 128 MB). Above 1,000 rows the whole saddle
/// point's LU costs more: a T6 Hertz on an elastic block at 60,856 DOFs with 1,027 active
/// node-to-segment rows took 12 UMFPACK factorisations (64 s of solve) after the tail factor
/// had been made; held on the tail, one factorisation and 17 s.
constexpr int kMaxCondensedSchurRows = 4000;
/// Columns of W = K_ρ⁻¹ Cᵀ solved at once: n × 32 doubles at a time (256 MB at 1M unknowns).
constexpr int kSchurBlock = 32;
constexpr double kMinSchurRcond = 1e-13;
constexpr double kMinCholeskyPivotRatio = 1e-11;
/// Gap rows in R at first: enough for a body floating in the contact direction, few enough
/// that W holds little beyond the active rows.
constexpr int kRegularisingRows = 8;
/// Largest tail for the condensed path: L₂₂ is dense, k² doubles (128 MB) and k³/3 flops in
/// the factorisation (21 GFlop, a second or two on two cores).
constexpr int kMaxTail = 4000;
/// Above this relative residual the condensed solve takes one step of iterative refinement
/// with the same factors (slender, ill-conditioned bodies; the Hertz cases stay near 1e-14).
constexpr double kRefineResidual = 1e-12;
constexpr int kRefineSteps = 3;
/// Runs `f` when the scope ends, whichever return ends it.
template <class F>
struct AtExit {
  F f;
  ~AtExit() { f(); }
};
// Spelled out: clang before 17 deduces no template arguments for an aggregate (P1816).
template <class F>
AtExit(F) -> AtExit<F>;
const char* kDependentRows =
    "saddle-point matrix is singular: linearly dependent constraint rows or an unsupported body";
}  // namespace

SaddlePointSolver::SaddlePointSolver(const ConstrainedProblem& p, double s) : p_(p), s_(s) {
  const int n = p.num_unknowns(), me = p.num_equalities(), m = p.num_gaps();
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(p.eq_jacobian.nonZeros() + p.gap_jacobian.nonZeros());
  for (int c = 0; c < p.eq_jacobian.outerSize(); ++c)
    for (SpMat::InnerIterator it(p.eq_jacobian, c); it; ++it)
      t.emplace_back(it.col(), it.row(), it.value());
  for (int c = 0; c < p.gap_jacobian.outerSize(); ++c)
    for (SpMat::InnerIterator it(p.gap_jacobian, c); it; ++it)
      t.emplace_back(it.col(), me + it.row(), it.value());
  ct_ = SpMat(n, me + m);
  ct_.setFromTriplets(t.begin(), t.end());
  s_columns_.resize(me + m);
  v_.resize(me + m);
  std::vector<char> touched(n, 0);
  for (const auto& e : t) touched[e.row()] = 1;
  for (int d = 0; d < n; ++d)
    if (touched[d]) tail_dofs_.push_back(d);
  if (p.ordering) {
    chol_.set_ordering(p.ordering, "corner_amd");
    tail_.set_ordering(p.ordering);
  }
}

SaddlePointSolver::~SaddlePointSolver() = default;

void SaddlePointSolver::stiffness_changed() {
  path_ = Path::kUnknown;
  rho_.resize(0);
  condensed_ = false;
  for (auto& c : s_columns_) c.resize(0);
  for (auto& v : v_) v.resize(0);
  cached_rhs_.resize(0);
}

bool SaddlePointSolver::factorize_regularised(int max_gap_rows) {
  const int n = p_.num_unknowns(), me = p_.num_equalities(), m = p_.num_gaps();
  // R: the equality rows and the `max_gap_rows` gap rows with the smallest initial gap (the
  // ones that hold a floating body first), within half the rows the Schur complement takes.
  const int cap = kMaxSchurRows / 2;
  if (me >= cap) return false;
  std::vector<int> gaps(m);
  for (int i = 0; i < m; ++i) gaps[i] = i;
  const int take = std::min({m, cap - me, max_gap_rows});
  std::partial_sort(gaps.begin(), gaps.begin() + take, gaps.end(),
                    [&](int a, int b) { return p_.gap0[a] < p_.gap0[b]; });
  std::vector<int> reg;
  for (int j = 0; j < me; ++j) reg.push_back(j);
  for (int i = 0; i < take; ++i) reg.push_back(me + gaps[i]);
  k_rho_ = regularised_stiffness(p_.stiffness, ct_, reg, rho_);  // kept: the factor refers to it
  condensed_ = false;
  if (!tail_dofs_.empty() && static_cast<int>(tail_dofs_.size()) <= kMaxTail &&
      static_cast<int>(tail_dofs_.size()) < n) {
    condensed_ = tail_.factorize(k_rho_, tail_dofs_) == SolveStatus::kConverged &&
                 tail_.report().pivot_ratio > kMinCholeskyPivotRatio;
    if (condensed_) return true;
    if (tail_.report().status == SolveStatus::kSingular) {  // K_ρ itself: no other factor helps
      rho_.resize(0);
      k_rho_.resize(0, 0);
      return false;
    }
  }
  if (chol_.factorize(k_rho_) == SolveStatus::kConverged &&
      chol_.report().pivot_ratio > kMinCholeskyPivotRatio)
    return true;
  rho_.resize(0);
  k_rho_.resize(0, 0);
  return false;
}

void SaddlePointSolver::sync_report() {
  const auto& c = chol_.report();
  const auto& t = tail_.report();
  const auto& l = lu_.report();
  report_.numeric_factorizations =
      c.numeric_factorizations + t.numeric_factorizations + l.numeric_factorizations;
  report_.symbolic_seconds = c.symbolic_seconds + t.symbolic_seconds + l.symbolic_seconds;
  report_.symbolic_analyses = c.symbolic_analyses + t.symbolic_analyses + l.symbolic_analyses;
  report_.numeric_seconds = c.numeric_seconds + t.numeric_seconds + l.numeric_seconds;
  report_.solve_seconds = c.solve_seconds + t.solve_seconds + l.solve_seconds + dense_seconds_;
  using Info = const core::FactorInfo&;
  static_cast<core::FactorInfo&>(report_) =
      path_ == Path::kLu ? Info(l) : condensed_ ? Info(t) : Info(c);
}

SolveStatus SaddlePointSolver::factorize(const std::vector<char>& active, bool all_rows,
                                         bool same_pattern) {
  const AtExit sync{[this] { sync_report(); }};
  const int n = p_.num_unknowns(), me = p_.num_equalities(), m = p_.num_gaps();
  if (path_ == Path::kUnknown) {
    // K_ρ with a few rows in R whether or not K alone is definite: one factorisation either
    // way (trying K first would cost a floating body two). If those rows leave a rigid mode
    // (pivot ratio below 1e-11: W would be meaningless), every row that fits; then LU.
    rho_.resize(0);
    bool spd = false;
    if (me + m == 0) {
      spd = chol_.factorize(p_.stiffness) == SolveStatus::kConverged &&
            chol_.report().pivot_ratio > kMinCholeskyPivotRatio;
    } else {
      spd = factorize_regularised(kRegularisingRows) ||
            (m > kRegularisingRows && factorize_regularised(m));
    }
    path_ = spd ? Path::kSchur : Path::kLu;
  }
  all_rows_ = all_rows;
  rows_.clear();
  positions_.clear();
  in_rows_.clear();
  size_ = n + me;
  for (int j = 0; j < me; ++j) rows_.push_back(j), positions_.push_back(n + j), in_rows_.push_back(1);
  for (int i = 0; i < m; ++i) {
    if (active[i]) {
      rows_.push_back(me + i), positions_.push_back(size_), in_rows_.push_back(1);
    } else if (rho_.size() > 0 && rho_[me + i] > 0) {
      rows_.push_back(me + i), positions_.push_back(all_rows ? size_ : -1), in_rows_.push_back(0);
    }
    if (all_rows || active[i]) ++size_;
  }
  const int k = static_cast<int>(rows_.size());
  if (path_ == Path::kSchur && k <= (condensed_ ? kMaxCondensedSchurRows : kMaxSchurRows)) {
    const SolveStatus st = factorize_schur();
    if (st == SolveStatus::kConverged || report_.rcond < kMinSchurRcond) return st;
  }
  // LU of the whole saddle point: K's factor does not solve to precision, or C is too large.
  const SolveStatus st =
      lu_.factorize(saddle_point_matrix(p_, active, s_, all_rows), same_pattern && path_ == Path::kLu);
  path_ = Path::kLu;
  report_ = lu_.report();
  return st;
}

SolveStatus SaddlePointSolver::schur_by_solves(Eigen::MatrixXd& schur) {
  const int n = p_.num_unknowns(), k = static_cast<int>(rows_.size());
  // Columns of S = C K_ρ⁻¹ Cᵀ over every row, for the rows new to the system: W = K_ρ⁻¹ Cᵀ
  // in blocks of kSchurBlock columns, each block reduced to C W at once (W is never kept).
  std::vector<int> missing;
  for (int j : rows_)
    if (s_columns_[j].size() == 0) missing.push_back(j);
  for (size_t first = 0; first < missing.size(); first += kSchurBlock) {
    const int cols = static_cast<int>(std::min<size_t>(kSchurBlock, missing.size() - first));
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, cols);
    for (int c = 0; c < cols; ++c)
      for (SpMat::InnerIterator it(ct_, missing[first + c]); it; ++it) rhs(it.row(), c) = it.value();
    Eigen::MatrixXd w;
    const SolveStatus st = chol_.solve(rhs, w);
    if (st != SolveStatus::kConverged) {
      report_.status = st;
      report_.message = chol_.report().message;
      return st;
    }
    const Eigen::MatrixXd cw = ct_.transpose() * w;
    for (int c = 0; c < cols; ++c) s_columns_[missing[first + c]] = cw.col(c);
  }
  schur.resize(k, k);
  for (int c = 0; c < k; ++c)
    for (int r = 0; r < k; ++r) schur(r, c) = s_columns_[rows_[c]][rows_[r]];
  return SolveStatus::kConverged;
}

void SaddlePointSolver::schur_condensed(Eigen::MatrixXd& schur) {
  const core::Stopwatch clock;
  const int k = static_cast<int>(rows_.size()), kt = tail_.tail_size();
  const auto& pos = tail_.tail_position();
  // V's columns for the rows new to the system: L₂₂⁻¹ c_j, one dense triangular solve for all.
  std::vector<int> missing;
  for (int j : rows_)
    if (v_[j].size() == 0) missing.push_back(j);
  if (!missing.empty()) {
    Eigen::MatrixXd block = Eigen::MatrixXd::Zero(kt, static_cast<Eigen::Index>(missing.size()));
    for (size_t c = 0; c < missing.size(); ++c)
      for (SpMat::InnerIterator it(ct_, missing[c]); it; ++it) block(pos[it.row()], c) = it.value();
    tail_.tail_factor().triangularView<Eigen::Lower>().solveInPlace(block);
    for (size_t c = 0; c < missing.size(); ++c) v_[missing[c]] = block.col(c);
  }
  Eigen::MatrixXd v(kt, k);
  for (int r = 0; r < k; ++r) v.col(r) = v_[rows_[r]];
  // S = Vᵀ D₂⁻¹ V (D₂ = I for an L Lᵀ factor; an L D Lᵀ one may hold negative pivots).
  schur = v.transpose() * (tail_.tail_pivots().cwiseInverse().asDiagonal() * v);
  dense_seconds_ += clock.elapsed();
}

SolveStatus SaddlePointSolver::factorize_schur() {
  const int n = p_.num_unknowns(), k = static_cast<int>(rows_.size());
  report_.message.clear();
  report_.rcond = 1.0;  // below kMinSchurRcond only when S itself is singular
  Eigen::MatrixXd schur;  // C K_ρ⁻¹ Cᵀ
  if (condensed_) {
    schur_condensed(schur);
  } else if (const SolveStatus st = schur_by_solves(schur); st != SolveStatus::kConverged) {
    return st;
  }
  std::vector<Eigen::Triplet<double>> t;
  for (int r = 0; r < k; ++r)
    for (SpMat::InnerIterator it(ct_, rows_[r]); it; ++it) t.emplace_back(r, it.row(), it.value());
  c_rows_ = SpMat(k, n);
  c_rows_.setFromTriplets(t.begin(), t.end());
  report_.status = SolveStatus::kConverged;
  report_.rcond = 1.0;
  if (k == 0) return report_.status;
  schur = 0.5 * (schur + schur.transpose()).eval();
  for (int r = 0; r < k; ++r)
    if (!in_rows_[r]) schur(r, r) -= 1.0 / rho_[rows_[r]];
  schur_.compute(schur);
  if (condensed_) schur_matrix_ = schur;
  // The LU's condition estimate, bounded by the pivot ratio of U (an exactly zero pivot).
  const VecX d = schur_.matrixLU().diagonal().cwiseAbs();
  const double dmax = d.maxCoeff();
  report_.rcond = dmax > 0 && d.allFinite() ? std::min(schur_.rcond(), d.minCoeff() / dmax) : 0.0;
  if (!(report_.rcond > kMinSchurRcond)) {
    report_.status = SolveStatus::kSingular;
    report_.message = std::string(kDependentRows) + " (Schur complement rcond " +
                      number_text(report_.rcond) + ")";
  }
  return report_.status;
}

SolveStatus SaddlePointSolver::solve(const VecX& b, VecX& x, bool surface_only) {
  const AtExit sync{[this] { sync_report(); }};
  if (path_ != Path::kSchur) {
    const SolveStatus st = lu_.solve(b, x);
    report_.status = lu_.report().status;
    report_.message = lu_.report().message;
    report_.relative_residual = lu_.report().relative_residual;
    return st;
  }
  if (report_.status != SolveStatus::kConverged) return report_.status;
  if (condensed_) {
    SolveStatus st = solve_condensed(b, x, surface_only);
    // Iterative refinement with the same factors while it pays (each step a tenth or less of
    // the residual before), at most kRefineSteps: near a limit point K_ρ is nearly singular.
    double before = report_.relative_residual;
    for (int step = 0; st == SolveStatus::kConverged || st == SolveStatus::kIllConditioned;) {
      if (surface_only || before <= kRefineResidual || step++ == kRefineSteps) break;
      const VecX kept_x = x;
      const KktSolveReport kept = report_;
      const SolveStatus refined = refine(b, x);
      if (report_.relative_residual < 0.1 * before) {
        st = refined;
        before = report_.relative_residual;
        continue;
      }
      if (report_.relative_residual < before) {
        st = refined;
      } else {  // no gain: the solution before this step stands
        x = kept_x;
        report_ = kept;
      }
      break;
    }
    return st;
  }
  const int n = p_.num_unknowns(), k = static_cast<int>(rows_.size());
  x = VecX::Zero(size_);
  VecX y;
  SolveStatus st = solve_k_rho(regularised_rhs(b), y);
  if (st != SolveStatus::kConverged) return st;
  if (all_rows_) solve_inactive_rows(b, x);
  VecX z = VecX::Zero(k);
  if (k > 0) {
    st = solve_multipliers(b, y, z, x);
    if (st != SolveStatus::kConverged) return st;
  }
  x.head(n) = y;
  check_solution(b, y, z, x);
  return report_.status;
}

SolveStatus SaddlePointSolver::solve_condensed(const VecX& b, VecX& x, bool surface_only) {
  const int n = p_.num_unknowns(), k = static_cast<int>(rows_.size()), kt = tail_.tail_size();
  x = VecX::Zero(size_);
  // K_ρ⁻¹ r = Pᵀ L⁻ᵀ w with w = (L D)⁻¹ P r: w is kept while r is (each set of an active-set
  // loop).
  const VecX r = regularised_rhs(b);
  if (r.size() != cached_rhs_.size() || r != cached_rhs_) {
    cached_rhs_.resize(0);
    if (const SolveStatus st = tail_.forward(r, cached_forward_); st != SolveStatus::kConverged) {
      report_.status = st;
      report_.message = tail_.report().message;
      return st;
    }
    cached_rhs_ = r;
  }
  VecX w = cached_forward_;
  if (all_rows_) solve_inactive_rows(b, x);
  VecX z = VecX::Zero(k);
  if (k > 0) {
    const core::Stopwatch clock;
    // C y = Vᵀ w₂ (y = K_ρ⁻¹ r, w₂ the tail of w); then u = y + s K_ρ⁻¹ Cᵀ z adds s D₂⁻¹ V z
    // to w₂.
    Eigen::MatrixXd v(kt, k);
    for (int c = 0; c < k; ++c) v.col(c) = v_[rows_[c]];
    VecX rhs = v.transpose() * w.tail(kt);
    for (int c = 0; c < k; ++c)
      rhs[c] = -((in_rows_[c] ? b[positions_[c]] : 0.0) + s_ * rhs[c]) / (s_ * s_);
    z = schur_.solve(rhs);
    if (surface_only) {
      const double rn = rhs.norm();
      report_.relative_residual = (schur_matrix_ * z - rhs).norm() / (rn > 0 ? rn : 1.0);
    }
    w.tail(kt) += s_ * (v * z).cwiseQuotient(tail_.tail_pivots());
    for (int c = 0; c < k; ++c)
      if (in_rows_[c])
        x[positions_[c]] = z[c];
      else
        z[c] = 0.0;  // an auxiliary unknown of R, not a multiplier
    dense_seconds_ += clock.elapsed();
  }
  if (surface_only) {
    // u on the tail: the last k rows of Pᵀ L⁻ᵀ w need only L₂₂ᵀ.
    const core::Stopwatch clock;
    const VecX yt = tail_.tail_factor().triangularView<Eigen::Lower>().transpose().solve(w.tail(kt));
    for (int d : tail_dofs_) x[d] = yt[tail_.tail_position()[d]];
    dense_seconds_ += clock.elapsed();
    if (k == 0) report_.relative_residual = 0.0;
    report_.status = x.allFinite() && std::isfinite(report_.relative_residual)
                         ? SolveStatus::kConverged
                         : SolveStatus::kFailed;
    if (report_.status != SolveStatus::kConverged)
      report_.message = "Schur-complement solve produced non-finite values";
    return report_.status;
  }
  VecX y;
  if (const SolveStatus st = tail_.backward(w, y); st != SolveStatus::kConverged) {
    report_.status = st;
    report_.message = tail_.report().message;
    return st;
  }
  x.head(n) = y;
  check_solution(b, y, z, x);
  return report_.status;
}

SolveStatus SaddlePointSolver::refine(const VecX& b, VecX& x) {
  const int n = p_.num_unknowns(), k = static_cast<int>(rows_.size());
  // The residual of the original rows, R = b − M x, solved with the same factors: x += M⁻¹ R.
  VecX z = VecX::Zero(k);
  for (int r = 0; r < k; ++r)
    if (in_rows_[r]) z[r] = x[positions_[r]];
  const VecX u = x.head(n);
  VecX residual = VecX::Zero(size_);
  residual.head(n) = b.head(n) - p_.stiffness * u + s_ * (c_rows_.transpose() * z);
  const VecX cu = c_rows_ * u;
  for (int r = 0; r < k; ++r)
    if (in_rows_[r]) residual[positions_[r]] = b[positions_[r]] + s_ * cu[r];
  VecX dx;
  if (const SolveStatus st = solve_condensed(residual, dx); st != SolveStatus::kConverged)
    return st;
  x += dx;
  for (int r = 0; r < k; ++r)
    if (in_rows_[r]) z[r] = x[positions_[r]];
  check_solution(b, VecX(x.head(n)), z, x);
  return report_.status;
}

VecX SaddlePointSolver::regularised_rhs(const VecX& b) const {
  const int n = p_.num_unknowns(), k = static_cast<int>(rows_.size());
  // Right-hand side of K_ρ: rows of R in the system satisfy C_r u = −b_r / s.
  VecX bu = b.head(n);
  if (rho_.size() > 0)
    for (int r = 0; r < k; ++r)
      if (in_rows_[r] && rho_[rows_[r]] > 0) {
        const double f = -rho_[rows_[r]] * b[positions_[r]] / s_;
        for (SpMat::InnerIterator it(ct_, rows_[r]); it; ++it) bu[it.row()] += f * it.value();
      }
  return bu;
}

SolveStatus SaddlePointSolver::solve_k_rho(const VecX& rhs, VecX& out) {
  const SolveStatus st = chol_.solve(rhs, out);
  if (st != SolveStatus::kConverged) {
    report_.status = st;
    report_.message = chol_.report().message;
  }
  return st;
}

void SaddlePointSolver::solve_inactive_rows(const VecX& b, VecX& x) const {
  const int n = p_.num_unknowns(), k = static_cast<int>(rows_.size());
  const int me = p_.num_equalities();
  // Inactive rows kept in the system: s z_i = b_i.
  int pos = n + me;
  std::vector<char> in_system(p_.num_gaps(), 0);
  for (int r = 0; r < k; ++r)
    if (in_rows_[r] && rows_[r] >= me) in_system[rows_[r] - me] = 1;
  for (int i = 0; i < p_.num_gaps(); ++i, ++pos)
    if (!in_system[i]) x[pos] = b[pos] / s_;
}

SolveStatus SaddlePointSolver::solve_multipliers(const VecX& b, VecX& y, VecX& z, VecX& x) {
  const int k = static_cast<int>(rows_.size());
  VecX rhs = c_rows_ * y;
  for (int r = 0; r < k; ++r)
    rhs[r] = -((in_rows_[r] ? b[positions_[r]] : 0.0) + s_ * rhs[r]) / (s_ * s_);
  z = schur_.solve(rhs);
  // u = y + s K_ρ⁻¹ Cᵀ z: one more solve, where a kept W would cost n × k memory.
  VecX dy;
  const SolveStatus st = solve_k_rho(VecX(c_rows_.transpose() * z), dy);
  if (st != SolveStatus::kConverged) return st;
  y += s_ * dy;
  for (int r = 0; r < k; ++r)
    if (in_rows_[r])
      x[positions_[r]] = z[r];
    else
      z[r] = 0.0;  // an auxiliary unknown of R, not a multiplier
  return st;
}

void SaddlePointSolver::check_solution(const VecX& b, const VecX& y, const VecX& z, VecX& x) {
  const int n = p_.num_unknowns(), k = static_cast<int>(rows_.size());
  // Residual of the original system's rows (the others are exact by construction).
  VecX ru = p_.stiffness * y - b.head(n);
  if (k > 0) ru -= s_ * (c_rows_.transpose() * z);
  double r2 = ru.squaredNorm(), b2 = b.head(n).squaredNorm();
  if (k > 0) {
    const VecX cy = c_rows_ * y;
    for (int r = 0; r < k; ++r) {
      if (!in_rows_[r]) continue;
      const double rc = -s_ * cy[r] - b[positions_[r]];
      r2 += rc * rc;
      b2 += b[positions_[r]] * b[positions_[r]];
    }
  }
  report_.relative_residual = std::sqrt(r2) / (b2 > 0 ? std::sqrt(b2) : 1.0);
  if (!x.allFinite()) {
    report_.status = SolveStatus::kFailed;
    report_.message = "Schur-complement solve produced non-finite values";
    x.setZero(size_);
  } else if (report_.relative_residual > 1e-6) {
    report_.status = SolveStatus::kIllConditioned;
    report_.message = "saddle-point solve residual " + number_text(report_.relative_residual);
  }
}

}  // namespace c2d::constraints
