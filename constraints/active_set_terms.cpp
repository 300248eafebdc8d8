#include "constraints/active_set_terms.hpp"

#include <algorithm>

#include "constraints/constrained_problem.hpp"
#include "constraints/saddle_point_solver.hpp"
#include "core/spd_solver.hpp"

namespace c2d::constraints {

namespace {

/// Whether two sparse matrices have one non-zero pattern (a factorisation's symbolic analysis
/// of one serves the other).
bool same_pattern(const SpMat& a, const SpMat& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols() || a.nonZeros() != b.nonZeros()) return false;
  if (!a.isCompressed() || !b.isCompressed()) return false;
  return std::equal(a.outerIndexPtr(), a.outerIndexPtr() + a.outerSize() + 1, b.outerIndexPtr()) &&
         std::equal(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros(), b.innerIndexPtr());
}

/// Forces as unknowns z = λ/s (the multiplier methods', and the penalty law's mixed form):
/// z of the active rows' forces, 0 elsewhere; and back, λ = s z on the active rows.
void pack_scaled_forces(const std::vector<char>& active, double s, const VecX& force,
                        Eigen::Ref<VecX> extra) {
  for (int i = 0; i < extra.size(); ++i) extra[i] = active[i] ? force[i] / s : 0.0;
}
VecX scaled_forces(const std::vector<char>& active, double s, const Eigen::Ref<const VecX>& extra,
                   int rows) {
  VecX f = VecX::Zero(rows);
  for (int i = 0; i < extra.size(); ++i)
    if (active[i]) f[i] = s * extra[i];
  return f;
}

/// K_T + G_Aᵀ diag(k_A) G_A on one CHOLMOD factor, its analysis kept while the pattern is:
/// the Newton matrix of both forms of the penalty law (k_A: k on the active rows, 0 elsewhere).
class PenalisedMatrix {
 public:
  PenalisedMatrix(const VecX& k, const std::vector<char>& active) : ka_(VecX::Zero(k.size())) {
    for (int i = 0; i < ka_.size(); ++i)
      if (active[i]) ka_[i] = k[i];
  }
  const VecX& k_active() const { return ka_; }
  void set_rows(const SpMat& g) { penalty_ = SpMat(SpMat(g.transpose()) * ka_.asDiagonal() * g); }
  bool factorize(const SpMat& k_t) {
    jacobian_ = k_t + penalty_;  // the solver keeps a reference for its residual check
    if (!same_pattern(jacobian_, pattern_)) {
      spd_.reset_pattern();
      pattern_ = jacobian_;
    }
    return spd_.factorize(jacobian_) == SolveStatus::kConverged;
  }
  bool solve(const VecX& b, VecX& x) { return spd_.solve(b, x) == SolveStatus::kConverged; }

 private:
  VecX ka_;
  SpMat penalty_, jacobian_, pattern_;
  core::SpdSolver spd_{core::SpdSolver::Backend::kCholmod, false};
};

/// The penalty law of the active rows in primal form: their forces λ̂ − k g_A(u) follow from
/// u, G_Aᵀ diag(k) G_A joins K_T (the augmented Lagrangian's, whose λ̂ each outer iteration's
/// method solve fixes anew at its exact crossover: the state's forces are the law's at u).
class PenaltyTerms final : public ActiveSetTerms {
 public:
  PenaltyTerms(const SpMat& g, const std::vector<char>& active, const VecX& k,
               const VecX& lambda_hat)
      : active_(active), k_(k), lambda_hat_(lambda_hat), matrix_(k, active) {
    const VecX& ka = matrix_.k_active();
    k_max_ = ka.size() ? ka.maxCoeff() : 0.0;
    update_rows(g);
  }
  void update_rows(const SpMat& g) override { matrix_.set_rows(g); }
  int extra_unknowns() const override { return 0; }
  void pack_forces(const VecX&, Eigen::Ref<VecX>) const override {}
  VecX forces(const VecX& gap, const Eigen::Ref<const VecX>&) const override {
    VecX f = VecX::Zero(gap.size());
    for (int i = 0; i < f.size(); ++i)
      if (active_[i]) f[i] = lambda_hat_[i] - k_[i] * gap[i];
    return f;
  }
  void extra_residual(const VecX&, const Eigen::Ref<const VecX>&, Eigen::Ref<VecX>) const override {}
  bool factorize(const SpMat& k_t) override { return matrix_.factorize(k_t); }
  bool solve(const VecX& b, VecX& x) override { return matrix_.solve(b, x); }
  double row_stiffness() const override { return k_max_; }

 private:
  std::vector<char> active_;
  VecX k_, lambda_hat_;
  PenalisedMatrix matrix_;
  double k_max_ = 0.0;
};

/// The penalty law of the active rows, λ_i = λ̂_i − k_i g_i(u), in mixed form: the forces are
/// unknowns z = λ/s beside u, as the multiplier methods' are, and the law is their equation,
/// weighed by s as the multiplier rows' g = 0 is:
///   r_u = R_s(u) − G_Aᵀ s z_A,   r_A = −s (g_A(u) + (s z_A − λ̂_A)/k_A),   r_I = s z_I.
/// At a solution it is the penalised equations R_s(u) − G_Aᵀ (λ̂ − k g_A) = 0. Measured so, a
/// row's gap error counts s·δg as an exact method's does, not k·δg: the penalty's force of a
/// gap missed by δg is off by k·δg, and the stop test in force units asked a penalised row's gap
/// to k/s times the precision of an exact method's (the frictional drag with the default
/// k ≈ 1000 s: a fourth Newton iterate a step, where lagrange needs three).
/// The Newton matrix is solved by eliminating z: (K_T + G_Aᵀ diag(k) G_A) du = b_u −
/// G_Aᵀ (k/s ∘ b_A), z_A = −(k/s²)(b_A + s G_A du), z_I = b_I / s, through one CHOLMOD factor.
class PenaltyLawTerms final : public ActiveSetTerms {
 public:
  PenaltyLawTerms(const SpMat& g, const std::vector<char>& active, const VecX& k,
                  const VecX& lambda_hat, double s)
      : active_(active), k_(k), lambda_hat_(lambda_hat), matrix_(k, active), s_(s),
        m_(static_cast<int>(g.rows())) {
    update_rows(g);
  }
  void update_rows(const SpMat& g) override {
    g_ = g;
    matrix_.set_rows(g);
  }
  int extra_unknowns() const override { return m_; }
  void pack_forces(const VecX& force, Eigen::Ref<VecX> extra) const override {
    pack_scaled_forces(active_, s_, force, extra);
  }
  VecX forces(const VecX& gap, const Eigen::Ref<const VecX>& extra) const override {
    return scaled_forces(active_, s_, extra, static_cast<int>(gap.size()));
  }
  void extra_residual(const VecX& gap, const Eigen::Ref<const VecX>& extra,
                      Eigen::Ref<VecX> r) const override {
    for (int i = 0; i < m_; ++i)
      r[i] = active_[i] ? -s_ * (gap[i] + (s_ * extra[i] - lambda_hat_[i]) / k_[i])
                        : s_ * extra[i];
  }
  bool factorize(const SpMat& k_t) override { return matrix_.factorize(k_t); }
  bool solve(const VecX& b, VecX& x) override {
    const int n = static_cast<int>(g_.cols());
    const VecX& ka = matrix_.k_active();
    const VecX bz = b.tail(m_);
    const VecX scaled = (ka / s_).cwiseProduct(bz);  // k/s ∘ b_A (0 on the inactive rows)
    VecX du;
    if (!matrix_.solve(VecX(b.head(n) - g_.transpose() * scaled), du)) return false;
    const VecX gdu = g_ * du;
    x.resize(n + m_);
    x.head(n) = du;
    for (int i = 0; i < m_; ++i)
      x[n + i] = active_[i] ? -ka[i] / (s_ * s_) * (bz[i] + s_ * gdu[i]) : bz[i] / s_;
    return true;
  }
  double row_stiffness() const override { return s_; }

 private:
  std::vector<char> active_;
  VecX k_, lambda_hat_;
  PenalisedMatrix matrix_;
  double s_;
  int m_;
  SpMat g_;
};

class MultiplierTerms final : public ActiveSetTerms {
 public:
  MultiplierTerms(const SpMat& g, const std::vector<char>& active, double s)
      : active_(active), s_(s), m_(static_cast<int>(g.rows())) {
    any_active_ = std::find(active_.begin(), active_.end(), 1) != active_.end();
    if (!any_active_) return;
    const int n = static_cast<int>(g.cols());
    problem_.gap0 = VecX::Zero(m_);
    problem_.load = VecX::Zero(n);
    problem_.eq_jacobian = SpMat(0, n);
    problem_.eq_rhs = VecX();
    update_rows(g);
  }
  void update_rows(const SpMat& g) override {
    if (!any_active_) return;
    problem_.gap_jacobian = g;  // the solver builds its rows from it: a new solver
    saddle_ = std::make_unique<SaddlePointSolver>(problem_, s_);
    analysed_ = false;
  }
  int extra_unknowns() const override { return any_active_ ? m_ : 0; }
  void pack_forces(const VecX& force, Eigen::Ref<VecX> extra) const override {
    pack_scaled_forces(active_, s_, force, extra);
  }
  VecX forces(const VecX& gap, const Eigen::Ref<const VecX>& extra) const override {
    return scaled_forces(active_, s_, extra, static_cast<int>(gap.size()));
  }
  void extra_residual(const VecX& gap, const Eigen::Ref<const VecX>& extra,
                      Eigen::Ref<VecX> r) const override {
    for (int i = 0; i < extra.size(); ++i) r[i] = active_[i] ? -s_ * gap[i] : s_ * extra[i];
  }
  bool factorize(const SpMat& k_t) override {
    const bool same = same_pattern(k_t, pattern_);
    if (!same) pattern_ = k_t;
    if (!any_active_) {
      if (!same) spd_.reset_pattern();
      return spd_.factorize(k_t) == SolveStatus::kConverged;
    }
    problem_.stiffness = k_t;
    saddle_->stiffness_changed();
    const bool ok = saddle_->factorize(active_, true, analysed_ && same) == SolveStatus::kConverged;
    analysed_ = true;
    return ok;
  }
  bool solve(const VecX& b, VecX& x) override {
    return (any_active_ ? saddle_->solve(b, x) : spd_.solve(b, x)) == SolveStatus::kConverged;
  }
  double row_stiffness() const override { return any_active_ ? s_ : 0.0; }

 private:
  std::vector<char> active_;
  double s_;
  int m_;
  bool any_active_ = false;
  ConstrainedProblem problem_;
  SpMat pattern_;
  std::unique_ptr<SaddlePointSolver> saddle_;
  bool analysed_ = false;
  core::SpdSolver spd_{core::SpdSolver::Backend::kCholmod, false};
};

}  // namespace

std::unique_ptr<ActiveSetTerms> make_penalty_terms(const SpMat& g, const std::vector<char>& active,
                                                   const VecX& k, const VecX& lambda_hat,
                                                   double s, bool forces_unknown) {
  if (!forces_unknown) return std::make_unique<PenaltyTerms>(g, active, k, lambda_hat);
  return std::make_unique<PenaltyLawTerms>(g, active, k, lambda_hat, s);
}

std::unique_ptr<ActiveSetTerms> make_multiplier_terms(const SpMat& g,
                                                      const std::vector<char>& active, double s) {
  return std::make_unique<MultiplierTerms>(g, active, s);
}

}  // namespace c2d::constraints
