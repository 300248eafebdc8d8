#include "constraints/methods/ssn_strategy.hpp"

#include "constraints/friction_solver.hpp"
#include "constraints/strategy_common.hpp"

namespace c2d::constraints {

ConstraintSolution SsnStrategy::solve_problem(const ConstrainedProblem& p,
                                              const RowMemory& memory) {
  if (p.has_friction()) return solve_frictional(p, memory, rule_, options_.max_iterations);
  ConstraintSolution s;
  // c has the units of a stiffness, so λ − c g compares a force with a force.
  const double c = saddle_point_scale(p);
  solve_active_set(
      p, memory, options_.max_iterations, true,
      [&](const ConstraintSolution& sol, const VecX& g, double, std::vector<char>& next) {
        return next_normal_set(rule_, p, sol.contact_force, g, VecX(), VecX(), c, next);
      },
      "Newton step", s);
  return s;
}

}  // namespace c2d::constraints
