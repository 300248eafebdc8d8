#include "constraints/methods/lagrange_strategy.hpp"

#include "constraints/friction_solver.hpp"
#include "constraints/strategy_common.hpp"

namespace c2d::constraints {

ConstraintSolution LagrangeStrategy::solve_problem(const ConstrainedProblem& p,
                                                   const RowMemory& memory) {
  if (p.has_friction()) return solve_frictional(p, memory, rule_, options_.max_iterations);
  ConstraintSolution s;
  // The reduced system changes size with the active set, so each iteration analyses anew.
  // The primal-dual rule: rows in tension leave, penetrating rows enter.
  const double c = saddle_point_scale(p);
  solve_active_set(
      p, memory, options_.max_iterations, false,
      [&](const ConstraintSolution& sol, const VecX& g, double, std::vector<char>& next) {
        return next_normal_set(rule_, p, sol.contact_force, g, VecX(), VecX(), c, next);
      },
      "iteration", s);
  return s;
}

}  // namespace c2d::constraints
