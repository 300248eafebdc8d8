#include "nonlinear/active_set_system.hpp"

#include <utility>

namespace c2d::nonlinear {

using namespace c2d::constraints;

ActiveSetSystem::ActiveSetSystem(StructuralSystem& base, const ContactSet& contact,
                                 const std::vector<GapRow>& rows, const SpMat& g, const VecX& c,
                                 std::unique_ptr<ActiveSetTerms> terms,
                                 const std::vector<char>& active, int linear_tail)
    : base_(base), contact_(contact), moving_(!base.is_linear()), template_(rows),
      active_(active), g_(g), gt_(g_.transpose()), g_template_(g), c_(c),
      terms_(std::move(terms)), n_(static_cast<int>(g_.cols())), linear_tail_(linear_tail) {}

VecX ActiveSetSystem::pack(const VecX& u, const VecX& force) const {
  VecX x(size());
  x.head(n_) = u;
  terms_->pack_forces(force, x.tail(size() - n_));
  return x;
}

bool ActiveSetSystem::gap(const VecX& x, VecX& g) {
  if (!moving_) {
    g = c_ + g_ * x.head(n_);
    return true;
  }
  if (!evaluate(x)) return false;
  g = gap_now_;
  return true;
}

VecX ActiveSetSystem::forces(const VecX& x, const VecX& gap) const {
  return terms_->forces(gap, x.tail(size() - n_));
}

bool ActiveSetSystem::residual(const VecX& x, VecX& r) {
  VecX ru, g;
  if (!base_.residual(x.head(n_), ru) || !gap(x, g)) return false;  // gap() updates G
  r.resize(size());
  r.head(n_) = ru - gt_ * forces(x, g);
  if (fixed_force_.size() == n_) r.head(n_) -= fixed_force_;
  terms_->extra_residual(g, x.tail(size() - n_), r.tail(size() - n_));
  return true;
}

bool ActiveSetSystem::factorize_jacobian(const VecX& x) {
  if (!base_.assemble_tangent(base_.full(x.head(n_)))) return false;
  if (!moving_) return terms_->factorize(base_.matrix());
  if (!evaluate(x, true)) return false;
  terms_->update_rows(g_);
  // The geometric stiffness of the compressive row forces. Far from the solution a penalty
  // row's force k·g can be far off, tensile even, where the strategy's linearised step missed
  // the gap by its curvature: a tensile force's term would turn the contact's stiffness over,
  // so it is left out (at a solution active rows are compressive: the tangent is exact there).
  // Should the matrix still not factorise, the iterate steps without the term, the line search
  // keeping it safe.
  VecX force = forces(x, gap_now_);
  if (curvature_bound_.size() == force.size())
    force = force.cwiseMin(curvature_bound_).cwiseMax(-curvature_bound_);
  jacobian_ = base_.matrix() +
              contact_.geometric_stiffness(rows_now_, force.head(num_gaps()).cwiseMax(0.0));
  if (!eq_now_.empty())
    jacobian_ += contact_.equality_geometric_stiffness(
        eq_now_, force.segment(num_gaps(), force.size() - num_gaps() - linear_tail_));
  return terms_->factorize(jacobian_) || terms_->factorize(base_.matrix());
}

std::string ActiveSetSystem::evaluation_failure() const {
  return lost_.empty() ? base_.evaluation_failure() : lost_;
}

bool ActiveSetSystem::evaluate(const VecX& x, bool curvature) {
  if (evaluated_ && x.head(n_) == at_ && (curved_ || !curvature)) return lost_.empty();
  const VecX full = base_.full(x.head(n_));
  const std::vector<GapRow> fresh = contact_.detect(full, false, curvature);
  curved_ = curvature;
  std::vector<int> by_slot(contact_.num_slots(), -1);
  for (size_t k = 0; k < fresh.size(); ++k) by_slot[fresh[k].slot] = static_cast<int>(k);
  const int m = num_gaps(), me = static_cast<int>(c_.size()) - m;
  rows_now_.resize(m);
  const VecX linear = c_ + g_template_ * x.head(n_);
  gap_now_ = linear;  // the equality rows stay linear
  lost_.clear();
  for (int i = 0; i < m; ++i) {
    const int k = by_slot[template_[i].slot];
    if (k >= 0) {
      rows_now_[i] = fresh[k];
      gap_now_[i] = fresh[k].gap;
    } else {
      rows_now_[i] = template_[i];
      if (active_[i])
        lost_ = "the active contact row of node " + std::to_string(template_[i].slave + 1) +
                " found no master";
    }
  }
  const int me_rows = me - linear_tail_;  // the equality rows proper
  if (me_rows > 0 && contact_.has_nonlinear_equalities()) {
    eq_now_ = contact_.equality_rows_at(full, false);
    gap_now_.segment(m, me_rows) = contact_.equality_values(eq_now_, full);
    g_ = stack_rows(stack_rows(contact_.gap_jacobian(rows_now_), contact_.equality_jacobian(eq_now_)),
                    g_template_.bottomRows(linear_tail_));
  } else {
    g_ = stack_rows(contact_.gap_jacobian(rows_now_), g_template_.bottomRows(me));
  }
  gt_ = g_.transpose();
  at_ = x.head(n_);
  evaluated_ = true;
  return lost_.empty();
}

}  // namespace c2d::nonlinear
