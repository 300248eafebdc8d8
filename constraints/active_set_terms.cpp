#include "constraints/active_set_terms.hpp"

#include <algorithm>

#include "constraints/constrained_problem.hpp"
#include "constraints/saddle_point_solver.hpp"
#include "core/spd_solver.hpp"

namespace c2d::constraints {

namespace {

class PenaltyTerms final : public ActiveSetTerms {
 public:
  PenaltyTerms(const SpMat& g, const std::vector<char>& active, const VecX& k,
               const VecX& lambda_hat)
      : active_(active), k_(k), lambda_hat_(lambda_hat) {
    VecX ka = VecX::Zero(static_cast<int>(active_.size()));
    for (int i = 0; i < ka.size(); ++i)
      if (active_[i]) ka[i] = k_[i], k_max_ = std::max(k_max_, k_[i]);
    penalty_ = SpMat(SpMat(g.transpose()) * ka.asDiagonal() * g);
  }
  int extra_unknowns() const override { return 0; }
  void pack_forces(const VecX&, Eigen::Ref<VecX>) const override {}
  VecX forces(const VecX& gap, const Eigen::Ref<const VecX>&) const override {
    VecX f = VecX::Zero(gap.size());
    for (int i = 0; i < f.size(); ++i)
      if (active_[i]) f[i] = lambda_hat_[i] - k_[i] * gap[i];
    return f;
  }
  void extra_residual(const VecX&, const Eigen::Ref<const VecX>&, Eigen::Ref<VecX>) const override {}
  bool factorize(const SpMat& k_t) override {
    jacobian_ = k_t + penalty_;  // the solver keeps a reference for its residual check
    return spd_.factorize(jacobian_) == SolveStatus::kConverged;
  }
  bool solve(const VecX& b, VecX& x) override {
    return spd_.solve(b, x) == SolveStatus::kConverged;
  }
  double row_stiffness() const override { return k_max_; }

 private:
  std::vector<char> active_;
  VecX k_, lambda_hat_;
  double k_max_ = 0.0;
  SpMat penalty_, jacobian_;
  core::SpdSolver spd_{core::SpdSolver::Backend::kCholmod, false};
};

class MultiplierTerms final : public ActiveSetTerms {
 public:
  MultiplierTerms(const SpMat& g, const std::vector<char>& active, double s)
      : active_(active), s_(s), m_(static_cast<int>(g.rows())) {
    any_active_ = std::find(active_.begin(), active_.end(), 1) != active_.end();
    if (!any_active_) return;
    const int n = static_cast<int>(g.cols());
    problem_.gap_jacobian = g;
    problem_.gap0 = VecX::Zero(m_);
    problem_.load = VecX::Zero(n);
    problem_.eq_jacobian = SpMat(0, n);
    problem_.eq_rhs = VecX();
    saddle_ = std::make_unique<SaddlePointSolver>(problem_, s_);
  }
  int extra_unknowns() const override { return any_active_ ? m_ : 0; }
  void pack_forces(const VecX& force, Eigen::Ref<VecX> extra) const override {
    for (int i = 0; i < extra.size(); ++i) extra[i] = active_[i] ? force[i] / s_ : 0.0;
  }
  VecX forces(const VecX& gap, const Eigen::Ref<const VecX>& extra) const override {
    VecX f = VecX::Zero(gap.size());
    for (int i = 0; i < extra.size(); ++i)
      if (active_[i]) f[i] = s_ * extra[i];
    return f;
  }
  void extra_residual(const VecX& gap, const Eigen::Ref<const VecX>& extra,
                      Eigen::Ref<VecX> r) const override {
    for (int i = 0; i < extra.size(); ++i) r[i] = active_[i] ? -s_ * gap[i] : s_ * extra[i];
  }
  bool factorize(const SpMat& k_t) override {
    if (!any_active_) return spd_.factorize(k_t) == SolveStatus::kConverged;
    problem_.stiffness = k_t;
    saddle_->stiffness_changed();
    const bool ok = saddle_->factorize(active_, true, analysed_) == SolveStatus::kConverged;
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
  std::unique_ptr<SaddlePointSolver> saddle_;
  bool analysed_ = false;
  core::SpdSolver spd_{core::SpdSolver::Backend::kCholmod, false};
};

}  // namespace

std::unique_ptr<ActiveSetTerms> make_penalty_terms(const SpMat& g, const std::vector<char>& active,
                                                   const VecX& k, const VecX& lambda_hat) {
  return std::make_unique<PenaltyTerms>(g, active, k, lambda_hat);
}

std::unique_ptr<ActiveSetTerms> make_multiplier_terms(const SpMat& g,
                                                      const std::vector<char>& active, double s) {
  return std::make_unique<MultiplierTerms>(g, active, s);
}

}  // namespace c2d::constraints
