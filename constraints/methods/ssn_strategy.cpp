#include "constraints/methods/ssn_strategy.hpp"

#include <algorithm>
#include <cmath>

#include "constraints/friction_solver.hpp"
#include "constraints/strategy_common.hpp"

namespace c2d::constraints {

ConstraintSolution SsnStrategy::solve_problem(const ConstrainedProblem& p) {
  if (p.has_friction())
    return solve_frictional(p, FrictionalOptions::Rule::kSemiSmooth, options_.max_iterations);
  ConstraintSolution s;
  // c has the units of a stiffness, so λ − c g compares a force with a force.
  const double c = saddle_point_scale(p);
  solve_active_set(
      p, options_.max_iterations, true,
      [&](const ConstraintSolution& sol, const VecX& g, double, std::vector<char>& next) {
        const int m = static_cast<int>(next.size());
        const VecX& lambda = sol.contact_force;
        const double lmax = m > 0 ? lambda.cwiseAbs().maxCoeff() : 0.0;
        const double eps = 1e-10 * std::max(lmax, c * 1e-12 * p.model_size);
        double complementarity = 0.0;
        for (int i = 0; i < m; ++i) {
          next[i] = lambda[i] - c * g[i] > eps;
          complementarity = std::max(
              complementarity, std::abs(lambda[i] - std::max(0.0, lambda[i] - c * g[i])));
        }
        return complementarity;
      },
      "Newton step", s);
  return s;
}

}  // namespace c2d::constraints
