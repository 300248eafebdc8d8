#include "constraints/constraint_strategy.hpp"

#include <chrono>

#include "constraints/method_registry.hpp"
#include "constraints/strategy_common.hpp"
#include "core/errors.hpp"

namespace c2d::constraints {

std::string StrategyOptions::validate() const {
  if (!find_method(method))
    return "method: expected " + method_list(" | ") + ", found '" + method + "'";
  if (penalty_k < 0) return "penalty.k: expected a stiffness > 0";
  if (!(penalty_factor > 0)) return "penalty.factor: expected a factor > 0";
  if (tolerance < 0) return "tolerance: expected a length >= 0";
  if (!(relative_tolerance > 0)) return "relative_tolerance: expected a value > 0";
  if (!(penalty_growth > 1)) return "penalty.growth: expected a factor > 1";
  if (!(max_penalty_factor >= 1)) return "penalty.max_factor: expected a factor >= 1";
  if (!(penetration_limit > 0)) return "penetration_limit: expected a fraction > 0";
  if (!(augmentation_factor > 0)) return "auglag.factor: expected a factor > 0";
  if (!(ipopt_tolerance > 0)) return "ipopt.tol: expected a tolerance > 0";
  if (max_iterations < 1) return "max_iterations: expected an integer >= 1";
  return {};
}

ConstraintSolution ConstraintStrategy::solve(const ConstrainedProblem& problem,
                                             const RowMemory& memory) {
  const auto t0 = std::chrono::steady_clock::now();
  ConstraintSolution s = solve_problem(problem, memory);
  s.method = name();
  finish_solution(problem, s);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return s;
}

std::unique_ptr<ConstraintStrategy> ConstraintStrategy::create(const StrategyOptions& o) {
  if (const std::string error = o.validate(); !error.empty()) throw InputError(error);
  return find_method(o.method)->create(o);
}

namespace {

std::vector<char> held_active(const ConstrainedProblem& p, const ConstraintSolution& s) {
  std::vector<char> active = s.active;
  active.resize(p.num_gaps() + p.num_equalities(), 1);
  return active;
}

}  // namespace

std::unique_ptr<ActiveSetTerms> RegularisedStrategy::active_set_terms(
    const ConstrainedProblem& p, const ConstraintSolution& s) const {
  // The reported force λ = λ̂ − k g at the solution's gaps fixes λ̂ for the solve; an equality
  // row's force μ = μ̂ − k (A u − b) likewise.
  const int m = p.num_gaps(), me = p.num_equalities();
  VecX lambda_hat = VecX::Zero(m + me), k(m + me);
  for (int i = 0; i < m; ++i)
    if (s.active[i]) lambda_hat[i] = s.contact_force[i] + s.penalty[i] * s.gap[i];
  k.head(m) = s.penalty;
  if (me > 0) {
    const VecX h = p.eq_jacobian * s.u - p.eq_rhs;
    k.tail(me) = s.eq_penalty;
    lambda_hat.tail(me) = s.eq_multiplier + s.eq_penalty.cwiseProduct(h);
  }
  return make_penalty_terms(stack_rows(p.gap_jacobian, p.eq_jacobian), held_active(p, s), k,
                            lambda_hat, saddle_point_scale(p), !augmented());
}

std::unique_ptr<ActiveSetTerms> ExactStrategy::active_set_terms(
    const ConstrainedProblem& p, const ConstraintSolution& s) const {
  return make_multiplier_terms(stack_rows(p.gap_jacobian, p.eq_jacobian), held_active(p, s),
                               saddle_point_scale(p));
}

void ConstraintStrategy::step_accepted(StepHistory converged) {
  accepted_ = std::move(converged);
  on_step_accepted();
}

void ConstraintStrategy::step_rejected() { on_step_rejected(); }

}  // namespace c2d::constraints
