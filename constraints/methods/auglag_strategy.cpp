#include "constraints/methods/auglag_strategy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "constraints/friction_solver.hpp"
#include "constraints/methods/penalty_strategy.hpp"
#include "constraints/strategy_common.hpp"

namespace c2d::constraints {

namespace {

/// The round-off of a multiplier update: the update k·g carries the gaps' round-off, ε × the
/// model's size, times k, so a change below it is noise. The rounds stop when the change is
/// below 1e-9 of the largest force or this (a slender beam held by a rigid cap, its
/// multipliers 1e-3, changed by 3e-11 from round to round at k ε L = 6.5e-11 and never met
/// the 1e-9 test on the condensed path).
double update_round_off(const ConstrainedProblem& p, const VecX& k_gap, const VecX& k_eq) {
  double k_max = k_gap.size() ? k_gap.maxCoeff() : 0.0;
  if (k_eq.size()) k_max = std::max(k_max, k_eq.maxCoeff());
  return k_max * std::numeric_limits<double>::epsilon() * p.model_size;
}

/// Alart and Curnier's augmented Lagrangian, with friction where the problem has it: each round
/// solves the penalised problem for the multiplier estimates (the return map of both rows,
/// Coulomb's bound from the trial normal force), then sets them to the forces found (Uzawa).
ConstraintSolution solve_rounds(const SetRule& rule, const ConstrainedProblem& p,
                                const RowMemory& memory, const StrategyOptions& opt,
                                const VecX& k_gap, const VecX& k_eq) {
  ConstraintSolution s;
  const double tol = penetration_tolerance(opt, p);
  VecX lambda = VecX::Zero(p.num_gaps()), mu = VecX::Zero(p.num_equalities());
  if (memory.initial_force.size() == p.num_gaps()) lambda = memory.initial_force.cwiseMax(0.0);
  FrictionalOptions o = penalised_friction(rule, p, memory, k_gap, lambda, k_eq, mu);
  o.max_iterations = opt.max_iterations;
  s.status = SolveStatus::kMaxIterations;
  std::string why = "penetration above tolerance or multipliers still changing after " +
                    std::to_string(opt.max_iterations) + " multiplier updates";
  double floor = update_round_off(p, k_gap, k_eq);
  if (o.k_tangent.size()) floor = std::max(floor, update_round_off(p, o.k_tangent, VecX()));
  ConstraintSolution previous;         // each round starts from the last round's sets
  FrictionalSolver solver(p, memory);  // and reuses its factor while they hold
  for (int round = 0; round < opt.max_iterations; ++round) {
    o.first_iteration = s.history.empty() ? 1 : s.history.back().iteration + 1;
    if (round > 0) {
      previous = s;
      o.start = &previous;
    }
    solver.solve(o, s);
    if (s.status != SolveStatus::kConverged) {
      why = s.message;
      break;
    }
    const VecX g = p.gap0 + p.gap_jacobian * s.u;
    const VecX h = p.eq_jacobian * s.u - p.eq_rhs;
    const double violation = h.size() ? h.cwiseAbs().maxCoeff() : 0.0;
    const double change = std::max({(s.contact_force - o.lambda_hat).lpNorm<Eigen::Infinity>(),
                                    (s.tangent_force - o.tangent_hat).lpNorm<Eigen::Infinity>(),
                                    (s.eq_multiplier - o.mu_hat).lpNorm<Eigen::Infinity>()});
    o.lambda_hat = s.contact_force;
    o.tangent_hat = s.tangent_force;
    o.mu_hat = s.eq_multiplier;
    s.history.back().residual = change;
    const double scale = std::max({s.contact_force.lpNorm<Eigen::Infinity>(),
                                   s.tangent_force.lpNorm<Eigen::Infinity>(),
                                   s.eq_multiplier.lpNorm<Eigen::Infinity>()});
    if (max_penetration(g) <= tol && violation <= tol &&
        change <= std::max(1e-9 * scale, floor)) {
      s.status = SolveStatus::kConverged;
      s.message.clear();
      break;
    }
    // With the sets as the last round's, the rounds converge to the exact solution of those
    // sets (for fixed sets the problem is linear); the exact solve on the same factor goes to
    // that limit at once when the primal-dual rule confirms it. Where rows are nearly
    // dependent (stick rows along a direction supports already hold) the Uzawa rounds
    // approach it by under 1 % a round.
    std::string why_not;
    if (round > 0 && s.active == previous.active && s.friction_state == previous.friction_state &&
        confirm_exactly(solver, 1, s, why_not)) {
      s.status = SolveStatus::kConverged;
      s.message.clear();
      break;
    }
    s.status = SolveStatus::kMaxIterations;
  }
  if (s.status != SolveStatus::kConverged) s.message = why;
  s.penalty = k_gap;
  s.eq_penalty = k_eq;
  return s;
}

}  // namespace

ConstraintStrategy::StateTest AugLagStrategy::state_test(const ConstrainedProblem& p) const {
  return {&state_rule_, penetration_tolerance(options_, p)};
}

ConstraintSolution AugLagStrategy::solve_problem(const ConstrainedProblem& p,
                                                 const RowMemory& memory) {
  VecX k_gap, k_eq;
  default_penalties(p, memory, 0.0, options_.augmentation_factor, k_gap, k_eq);
  return solve_rounds(set_rule(), p, memory, options_, k_gap, k_eq);
}

}  // namespace c2d::constraints
