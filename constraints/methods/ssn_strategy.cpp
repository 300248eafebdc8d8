#include "constraints/methods/ssn_strategy.hpp"

#include "constraints/friction_solver.hpp"
#include "constraints/strategy_common.hpp"

namespace c2d::constraints {

ConstraintSolution SsnStrategy::solve_problem(const ConstrainedProblem& p,
                                              const RowMemory& memory) {
  return solve_frictional(p, memory, rule_, options_.max_iterations);
}

}  // namespace c2d::constraints
