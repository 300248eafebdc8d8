#include "constraints/methods/lagrange_strategy.hpp"

#include <algorithm>

#include "constraints/friction_solver.hpp"
#include "constraints/strategy_common.hpp"

namespace c2d::constraints {

ConstraintSolution LagrangeStrategy::solve_problem(const ConstrainedProblem& p) {
  if (p.has_friction())
    return solve_frictional(p, FrictionalOptions::Rule::kPrimalDual, options_.max_iterations);
  ConstraintSolution s;
  const double gap_tol = 1e-12 * p.model_size;
  // The reduced system changes size with the active set, so each iteration analyses anew.
  // Rows in tension leave, penetrating rows enter.
  solve_active_set(
      p, options_.max_iterations, false,
      [&](const ConstraintSolution& sol, const VecX& g, double linear_residual,
          std::vector<char>& next) {
        const int m = static_cast<int>(next.size());
        const double force_tol =
            1e-10 * (m > 0 ? std::max(sol.contact_force.cwiseAbs().maxCoeff(), 1e-300) : 1.0);
        const std::vector<char> active = next;
        for (int i = 0; i < m; ++i) {
          if (active[i] && sol.contact_force[i] < -force_tol) next[i] = 0;  // tension: release
          if (!active[i] && g[i] < -gap_tol) next[i] = 1;                 // penetration: close
        }
        return linear_residual;
      },
      "iteration", s);
  return s;
}

}  // namespace c2d::constraints
