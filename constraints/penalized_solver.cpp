#include "constraints/penalized_solver.hpp"

#include <algorithm>
#include <cmath>

namespace c2d::constraints {

PenalizedSolver::PenalizedSolver(const ConstrainedProblem& p, const SetRule& rule)
    : p_(p), rule_(rule), gt_(p.gap_jacobian.transpose()), at_(p.eq_jacobian.transpose()) {
  if (p.ordering) solver_.set_ordering(p.ordering, "corner_amd");
}

bool PenalizedSolver::surface_ready() {
  if (surface_tried_) return surface_ != nullptr;
  surface_tried_ = true;
  const int me = p_.num_equalities(), m = p_.num_gaps();
  if (me + m == 0) return false;
  SpMat ct(p_.num_unknowns(), me + m);  // the rows' columns: equalities first, then gaps
  if (me > 0) ct.leftCols(me) = at_;
  if (m > 0) ct.rightCols(m) = gt_;
  std::vector<int> eq(me);
  for (int j = 0; j < me; ++j) eq[j] = j;
  std::vector<std::vector<int>> groups(m);
  for (int i = 0; i < m; ++i) groups[i] = {me + i};
  surface_ = condense_onto_rows(std::move(ct), p_.stiffness, p_.ordering, eq, std::move(groups),
                                std::vector<double>(p_.gap0.begin(), p_.gap0.end()));
  return surface_ != nullptr;
}

SolveStatus PenalizedSolver::solve_condensed(const std::vector<char>& set, const VecX& k_gap,
                                             const VecX& lambda, const VecX& k_eq,
                                             const VecX& mu, VecX& u, bool tail_only) {
  // A closed row: g + (w − λ̂)/k = 0, i.e. G u + w/k = −g0 + λ̂/k; an equality row:
  // A u + w/k = b + μ/k. Compliance 1/k, so a stiff penalty only makes the block exact.
  const int me = p_.num_equalities(), m = p_.num_gaps();
  SurfaceCondensation::RowStates states;
  for (int j = 0; j < me; ++j) {
    if (!(k_eq[j] > 0)) return SolveStatus::kFailed;
    const double c = 1.0 / k_eq[j];
    states.hold(j, c, p_.eq_rhs[j] + c * mu[j]);
  }
  for (int i = 0; i < m; ++i) {
    if (!set[i]) continue;
    if (!(k_gap[i] > 0)) return SolveStatus::kFailed;
    const double c = 1.0 / k_gap[i];
    states.hold(me + i, c, -p_.gap0[i] + c * lambda[i]);
  }
  double rcond = 0.0;
  SolveStatus st = surface_->solve(p_.load, states, last_w_, u, rcond);
  last_states_ = std::move(states);
  if (st == SolveStatus::kConverged && !tail_only) st = surface_->complete(u);
  return st;
}

VecX PenalizedSolver::gaps(const VecX& u) const {
  return p_.num_gaps() > 0 ? VecX(p_.gap0 + p_.gap_jacobian * u) : VecX();
}

VecX PenalizedSolver::penalised_gap_forces(const VecX& u, const VecX& k_gap,
                                           const VecX& lambda) const {
  return p_.num_gaps() > 0 ? VecX(lambda - k_gap.cwiseProduct(gaps(u))) : VecX();
}

VecX PenalizedSolver::penalised_eq_forces(const VecX& u, const VecX& k_eq, const VecX& mu) const {
  return p_.num_equalities() > 0
             ? VecX(mu - k_eq.cwiseProduct(p_.eq_jacobian * u - p_.eq_rhs))
             : VecX();
}

double PenalizedSolver::force_round_off(const VecX& k_gap, const VecX& lambda, const VecX& k_eq,
                                        const VecX& mu, const VecX& u) const {
  const int m = p_.num_gaps(), me = p_.num_equalities();
  if (kept_w_.size() != me + m) return 0.0;
  const VecX gap_force = penalised_gap_forces(u, k_gap, lambda);
  const VecX eq_force = penalised_eq_forces(u, k_eq, mu);
  double largest = 0.0;
  for (int j = 0; j < me; ++j) largest = std::max(largest, std::abs(eq_force[j] - kept_w_[j]));
  for (int i = 0; i < m; ++i)
    if (kept_w_[me + i] > 0)
      largest = std::max(largest, std::abs(gap_force[i] - kept_w_[me + i]));
  return largest;
}

double PenalizedSolver::unresolved_penetration(const VecX& w, const VecX& k_gap,
                                               const VecX& u) const {
  const int m = p_.num_gaps();
  if (m == 0 || w.size() != m || u.size() != p_.num_unknowns()) return 0.0;
  const double significant = 1e-6 * w.cwiseAbs().maxCoeff();
  const VecX spread = p_.gap_jacobian.cwiseAbs() * u.cwiseAbs();
  double worst = 0.0;
  for (int i = 0; i < m; ++i) {
    if (!(w[i] > significant)) continue;
    const double round_off =
        16 * std::numeric_limits<double>::epsilon() * (std::abs(p_.gap0[i]) + spread[i]);
    worst = std::max(worst, round_off / (w[i] / k_gap[i]));
  }
  return worst;
}

void PenalizedSolver::forces(const VecX& k_gap, const VecX& lambda, const VecX& k_eq,
                             const VecX& mu, ConstraintSolution& s) const {
  const int m = p_.num_gaps(), me = p_.num_equalities();
  const bool exact = kept_w_.size() == me + m;
  s.contact_force = (exact ? VecX(kept_w_.tail(m)) : penalised_gap_forces(s.u, k_gap, lambda))
                        .cwiseMax(0.0);
  s.active.assign(m, 0);
  for (int i = 0; i < m; ++i) s.active[i] = s.contact_force[i] > 0;
  s.eq_multiplier = exact ? VecX(kept_w_.head(me)) : penalised_eq_forces(s.u, k_eq, mu);
  s.penalty = k_gap;
  s.eq_penalty = k_eq;
}

void PenalizedSolver::complete(VecX& u) {
  if (!surface_last_) return;
  VecX whole;
  if (surface_->complete(whole) != SolveStatus::kConverged) return;
  u = std::move(whole);
  VecX r_u, r_rows, du, dw;
  double before = residual(u, last_w_, r_u, r_rows);
  for (int step = 0; step < 3 && before > 1e-12; ++step) {
    // The correction solves the same rows with the residuals as load and targets.
    SurfaceCondensation::RowStates correction = last_states_;
    for (size_t h = 0; h < correction.held.size(); ++h)
      correction.target[h] = r_rows[static_cast<int>(h)] * correction.compliance[h];
    double rcond = 0.0;
    if (surface_->solve(r_u, correction, dw, du, rcond) != SolveStatus::kConverged ||
        surface_->complete(du) != SolveStatus::kConverged)
      return;
    const VecX u_next = u + du, w_next = last_w_ + dw;
    VecX r_u_next, r_rows_next;
    const double after = residual(u_next, w_next, r_u_next, r_rows_next);
    if (!(after < before)) return;  // no gain: the solution before this step stands
    u = u_next, last_w_ = w_next, r_u = r_u_next, r_rows = r_rows_next;
    const bool paid = after < 0.1 * before;
    before = after;
    if (!paid) return;
  }
}

double PenalizedSolver::residual(const VecX& u, const VecX& w, VecX& r_u, VecX& r_rows) const {
  const int me = p_.num_equalities(), m = p_.num_gaps();
  r_u = p_.load - p_.stiffness * u;
  if (me > 0) r_u += at_ * w.head(me);
  if (m > 0) r_u += gt_ * w.tail(m);
  double scale = p_.load.size() ? p_.load.cwiseAbs().maxCoeff() : 0.0;
  if (w.size()) scale = std::max(scale, w.cwiseAbs().maxCoeff());
  const int nh = static_cast<int>(last_states_.held.size());
  r_rows.resize(nh);
  double largest = r_u.size() ? r_u.cwiseAbs().maxCoeff() : 0.0;
  const VecX au = p_.eq_jacobian * u, gu = p_.gap_jacobian * u;
  for (int h = 0; h < nh; ++h) {
    const int r = last_states_.held[h];
    const double cu = r < me ? au[r] : gu[r - me];
    // As a force: k (target − c·u) − w, the compliance 1/k.
    r_rows[h] = (last_states_.target[h] - cu) / last_states_.compliance[h] - w[r];
    largest = std::max(largest, std::abs(r_rows[h]));
  }
  return scale > 0 ? largest / scale : largest;
}

void PenalizedSolver::report_counts(ConstraintSolution& s) const {
  const core::SpdSolveReport none;  // the figures of both paths, summed
  s.factorizations = 0, s.symbolic_analyses = 0;
  s.symbolic_seconds = s.numeric_seconds = s.solve_seconds = 0.0;
  add_solver_work(solver_.report(), none, s);
  if (surface_) {
    add_solver_work(surface_->report(), none, s);
    s.solve_seconds += surface_->dense_seconds();
  }
  const core::SpdSolveReport& last = surface_last_ ? surface_->report() : solver_.report();
  s.factor = last;
  s.pivot_ratio = last.pivot_ratio;
}

SolveStatus PenalizedSolver::solve_set(const std::vector<char>& set, const VecX& k_gap,
                                       const VecX& lambda, const VecX& k_eq, const VecX& mu,
                                       const VecX& rhs_eq, VecX& u, bool tail_only) {
  if (surface_ready() &&
      solve_condensed(set, k_gap, lambda, k_eq, mu, u, tail_only) == SolveStatus::kConverged) {
    surface_last_ = true;
    return SolveStatus::kConverged;
  }
  surface_last_ = false;
  const int m = p_.num_gaps();
  VecX k_set(m), w(m);
  for (int i = 0; i < m; ++i) {
    k_set[i] = set[i] ? k_gap[i] : 0.0;
    w[i] = set[i] ? lambda[i] - k_gap[i] * p_.gap0[i] : 0.0;
  }
  VecX rhs = p_.load;
  if (m > 0) rhs += gt_ * w;
  if (p_.num_equalities() > 0) rhs += rhs_eq;
  SolveStatus st = SolveStatus::kConverged;
  if (!factored_ || set != factored_set_ || k_gap != factored_k_gap_ || k_eq != factored_k_eq_) {
    kp_ = p_.stiffness;
    if (m > 0) kp_ += SpMat(gt_ * k_set.asDiagonal() * p_.gap_jacobian);
    if (p_.num_equalities() > 0) kp_ += SpMat(at_ * k_eq.asDiagonal() * p_.eq_jacobian);
    st = solver_.factorize(kp_);
    factored_ = st == SolveStatus::kConverged;
    factored_set_ = set;
    factored_k_gap_ = k_gap;
    factored_k_eq_ = k_eq;
  }
  if (st == SolveStatus::kConverged) st = solver_.solve(rhs, u);
  return st;
}

PenalizedSolver::Outcome PenalizedSolver::solve(const VecX& k_gap, const VecX& lambda,
                                                const VecX& k_eq, const VecX& mu,
                                                int max_iterations, std::vector<char>& active,
                                                VecX& u, std::vector<IterationRecord>& history,
                                                int first_iteration) {
  Outcome out;
  const int m = p_.num_gaps();
  kept_w_ = VecX();
  ActiveSetTracker tracker;
  tracker.record(active);
  StallMonitor stall;
  std::string why =
      "active set still changing after " + std::to_string(max_iterations) + " iterations";
  const VecX rhs_eq =
      p_.num_equalities() > 0 ? VecX(at_ * (mu + k_eq.cwiseProduct(p_.eq_rhs))) : VecX();
  for (int it = 1; it <= max_iterations; ++it) {
    out.status = solve_set(active, k_gap, lambda, k_eq, mu, rhs_eq, u, true);
    out.iterations = it;
    if (out.status != SolveStatus::kConverged) {
      out.message = solver_.report().message;
      return out;
    }
    VecX g = gaps(u);
    // A held row on the condensed surface: its gap from its force, g = (λ̂ − w)/k, as its row
    // of the block states it. From u, a stiff penalty's gap (1000 N / 1e20 N/mm) sits at the
    // round-off of the tail's displacements, and its sign is noise.
    if (surface_last_ && last_w_.size() == p_.num_equalities() + m)
      for (int i = 0; i < m; ++i)
        if (active[i]) g[i] = (lambda[i] - last_w_[p_.num_equalities() + i]) / k_gap[i];
    std::vector<char> next = active;
    next_normal_set(rule_, p_, VecX(), g, k_gap, lambda, 0.0, next);
    const auto change = tracker.record(next);
    IterationRecord rec =
        make_record(first_iteration + it - 1, next, change, g,
                    surface_last_ ? surface_->relative_residual()
                                  : solver_.report().relative_residual);
    rec.penalty =
        std::max(m > 0 ? k_gap.maxCoeff() : 0.0, p_.num_equalities() > 0 ? k_eq.maxCoeff() : 0.0);
    history.push_back(rec);
    if (change.unchanged) {
      complete(u);
      kept_w_ = surface_last_ ? last_w_ : VecX();
      return out;
    }
    if (change.repeated) {
      why = "the penalised active set returned to an earlier set after " + std::to_string(it) +
            " iterations";
      break;
    }
    if (!stall.progress(change)) {
      why = "the penalised active set not settling after " + std::to_string(it) + " iterations";
      break;
    }
    active = next;
  }
  complete(u);
  kept_w_ = VecX();  // the safeguard's state: its forces from u
  // The set cycles or wanders: the safeguard finishes from the last set, or names why not.
  const int first = history.empty() ? first_iteration : history.back().iteration + 1;
  ConstraintSolution state;
  state.history.swap(history);
  std::string message;
  auto solve_one = [&](const std::vector<char>& set, ConstraintSolution& out_set,
                       std::string& error) {
    const SolveStatus st = solve_set(set, k_gap, lambda, k_eq, mu, rhs_eq, out_set.u, false);
    if (st != SolveStatus::kConverged) {
      error = solver_.report().message;
      return st;
    }
    out_set.contact_force = penalised_gap_forces(out_set.u, k_gap, lambda);
    for (int i = 0; i < m; ++i)
      if (!set[i]) out_set.contact_force[i] = 0.0;
    out_set.eq_multiplier = penalised_eq_forces(out_set.u, k_eq, mu);
    return SolveStatus::kConverged;
  };
  VecX shift = VecX::Zero(m);
  for (int i = 0; i < m; ++i) shift[i] = lambda[i] / k_gap[i];
  out.status = dual_active_set(p_, solve_one, shift, max_iterations + 2 * m, first - 1, active,
                               state, message);
  history.swap(state.history);
  if (state.u.size() == p_.num_unknowns()) u = state.u;
  out.iterations =
      history.empty() ? out.iterations : history.back().iteration - first_iteration + 1;
  if (out.status != SolveStatus::kConverged) out.message = why + "; " + message;
  return out;
}

}  // namespace c2d::constraints
