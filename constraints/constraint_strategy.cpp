#include "constraints/constraint_strategy.hpp"

#include <chrono>

#include "constraints/adaptive_penalty_strategy.hpp"
#include "constraints/auglag_strategy.hpp"
#include "constraints/ipopt_strategy.hpp"
#include "constraints/lagrange_strategy.hpp"
#include "constraints/penalty_strategy.hpp"
#include "constraints/ssn_strategy.hpp"
#include "constraints/strategy_common.hpp"
#include "core/errors.hpp"

namespace c2d::constraints {

const std::vector<std::string>& method_names() {
  static const std::vector<std::string> names = {"penalty", "adaptive_penalty", "lagrange",
                                                 "auglag",  "ipopt",            "ssn"};
  return names;
}

bool is_exact_method(const std::string& m) {
  return m == "lagrange" || m == "ipopt" || m == "ssn";
}

std::string StrategyOptions::validate() const {
  bool known = false;
  for (const auto& n : method_names()) known |= n == method;
  if (!known)
    return "method: expected penalty | adaptive_penalty | lagrange | auglag | ipopt | ssn, found '" +
           method + "'";
  if (penalty_k < 0) return "penalty.k: expected a stiffness > 0";
  if (!(penalty_factor > 0)) return "penalty.factor: expected a factor > 0";
  if (tolerance < 0) return "tolerance: expected a length >= 0";
  if (!(relative_tolerance > 0)) return "relative_tolerance: expected a value > 0";
  if (!(penalty_growth > 1)) return "adaptive.growth: expected a factor > 1";
  if (!(max_penalty_factor >= 1)) return "adaptive.max_factor: expected a factor >= 1";
  if (!(augmentation_factor > 0)) return "auglag.factor: expected a factor > 0";
  if (!(ipopt_tolerance > 0)) return "ipopt.tol: expected a tolerance > 0";
  if (max_iterations < 1) return "max_iterations: expected an integer >= 1";
  return {};
}

ConstraintSolution ConstraintStrategy::solve(const ConstrainedProblem& problem) {
  const auto t0 = std::chrono::steady_clock::now();
  ConstraintSolution s = solve_problem(problem);
  s.method = name();
  finish_solution(problem, s);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return s;
}

std::unique_ptr<ConstraintStrategy> ConstraintStrategy::create(const StrategyOptions& o) {
  if (const std::string error = o.validate(); !error.empty()) throw InputError(error);
  if (o.method == "penalty") return std::make_unique<PenaltyStrategy>(o);
  if (o.method == "adaptive_penalty") return std::make_unique<AdaptivePenaltyStrategy>(o);
  if (o.method == "lagrange") return std::make_unique<LagrangeStrategy>(o);
  if (o.method == "auglag") return std::make_unique<AugLagStrategy>(o);
  if (o.method == "ipopt") return std::make_unique<IpoptStrategy>(o);
  return std::make_unique<SsnStrategy>(o);
}

}  // namespace c2d::constraints
