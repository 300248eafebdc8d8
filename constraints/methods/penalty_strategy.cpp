#include "constraints/methods/penalty_strategy.hpp"

#include <cmath>
#include <cstdio>

#include "constraints/friction_solver.hpp"
#include "constraints/strategy_common.hpp"

namespace c2d::constraints {

void default_penalties(const ConstrainedProblem& p, double absolute_k, double factor, VecX& k_gap,
                       VecX& k_eq) {
  const VecX local_gap = p.gap_local_stiffness();
  const VecX local_eq = p.row_stiffness(p.eq_jacobian);
  auto pick = [&](const VecX& local, int i) {
    return absolute_k > 0 ? absolute_k : factor * (local[i] > 0 ? local[i] : 1.0);
  };
  k_gap.resize(p.num_gaps());
  for (int i = 0; i < p.num_gaps(); ++i)
    k_gap[i] = p.gap_penalty.size() == p.num_gaps() && p.gap_penalty[i] > 0 ? p.gap_penalty[i]
                                                                            : pick(local_gap, i);
  k_eq.resize(p.num_equalities());
  for (int j = 0; j < p.num_equalities(); ++j) k_eq[j] = pick(local_eq, j);
}

void penalty_forces(const ConstrainedProblem& p, const VecX& k_gap, const VecX& lambda,
                    const VecX& k_eq, const VecX& mu, ConstraintSolution& s) {
  const int m = p.num_gaps();
  s.contact_force = VecX::Zero(m);
  s.active.assign(m, 0);
  if (m > 0) {
    const VecX g = p.gap0 + p.gap_jacobian * s.u;
    for (int i = 0; i < m; ++i) {
      s.contact_force[i] = std::max(0.0, lambda[i] - k_gap[i] * g[i]);
      s.active[i] = s.contact_force[i] > 0;
    }
  }
  s.eq_multiplier = p.num_equalities() > 0
                        ? VecX(mu - k_eq.cwiseProduct(p.eq_jacobian * s.u - p.eq_rhs))
                        : VecX();
  s.penalty = k_gap;
  s.eq_penalty = k_eq;
}

FrictionalOptions penalised_friction(const SetRule& rule, const ConstrainedProblem& p,
                                     const VecX& k_gap, const VecX& lambda, const VecX& k_eq,
                                     const VecX& mu) {
  FrictionalOptions o;
  o.rule = &rule;
  o.k_gap = k_gap;
  o.k_tangent = tangent_penalties(p, k_gap);
  o.k_eq = k_eq;
  o.lambda_hat = lambda;
  o.mu_hat = mu;
  // The return map's tangential spring starts from the force of the last converged state.
  o.tangent_hat = p.tangent_force0.size() == p.num_gaps() ? p.tangent_force0
                                                          : VecX(VecX::Zero(p.num_gaps()));
  return o;
}

namespace {
// Largest ratio of a row's penalty to its local stiffness: how many digits the penalty costs.
// Rows whose local stiffness is not positive (a tangent that lost definiteness around a
// collapsing element) have no such measure and are left out: their trouble is not the penalty.
double penalty_ratio(const ConstrainedProblem& p, const VecX& k_gap, const VecX& k_eq) {
  double r = 0.0;
  const VecX lg = p.gap_local_stiffness(), le = p.row_stiffness(p.eq_jacobian);
  for (int i = 0; i < k_gap.size(); ++i)
    if (lg[i] > 0) r = std::max(r, k_gap[i] / lg[i]);
  for (int j = 0; j < k_eq.size(); ++j)
    if (le[j] > 0) r = std::max(r, k_eq[j] / le[j]);
  return r;
}
}  // namespace

ConstraintSolution PenaltyStrategy::solve_problem(const ConstrainedProblem& p) {
  ConstraintSolution s;
  VecX k_gap, k_eq;
  default_penalties(p, options_.penalty_k, options_.penalty_factor, k_gap, k_eq);
  const VecX zero_gap = VecX::Zero(p.num_gaps()), zero_eq = VecX::Zero(p.num_equalities());
  if (p.has_friction()) {
    FrictionalOptions o = penalised_friction(set_rule(), p, k_gap, zero_gap, k_eq, zero_eq);
    o.max_iterations = options_.max_iterations;
    solve_frictional(p, o, s);
  } else {
    std::vector<char> active = initially_closed(p);
    PenalizedSolver solver(p, set_rule());
    const auto outcome = solver.solve(k_gap, zero_gap, k_eq, zero_eq, options_.max_iterations,
                                      active, s.u, s.history, 1);
    s.status = outcome.status;
    s.message = outcome.message;
    solver.report_counts(s);
  }
  // A penalty many orders above the element stiffness leaves the factorization nothing but
  // round-off: say so instead of returning what it produced.
  const double ratio = penalty_ratio(p, k_gap, k_eq);
  const double pivot = s.pivot_ratio;
  if (ratio > 1e6 && (s.status == SolveStatus::kSingular || pivot < 1e-12)) {
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "penalty k is %.3g x the local element stiffness; the factor's pivot ratio "
                  "%.3g leaves no significant digits (lower k or use an exact method)",
                  ratio, pivot);
    s.status = SolveStatus::kIllConditioned;
    s.message = buf;
  }
  if (p.has_friction()) {
    s.eq_penalty = k_eq;  // the frictional solve reports the forces of its sets
  } else if (s.status == SolveStatus::kConverged || s.status == SolveStatus::kCycling ||
             s.status == SolveStatus::kMaxIterations) {
    penalty_forces(p, k_gap, zero_gap, k_eq, zero_eq, s);
  }
  else
    s.u = VecX::Zero(p.num_unknowns());
  s.penalty = k_gap;
  return s;
}

}  // namespace c2d::constraints
