#include "constraints/methods/adaptive_penalty_strategy.hpp"

#include <cmath>
#include <memory>

#include "constraints/methods/penalty_strategy.hpp"
#include "constraints/strategy_common.hpp"
#include "core/errors.hpp"

namespace c2d::constraints {

ConstraintSolution AdaptivePenaltyStrategy::solve_problem(const ConstrainedProblem& p,
                                                          const RowMemory& memory) {
  ConstraintSolution s;
  VecX k_gap, k_eq;
  default_penalties(p, memory, 0.0, 1.0, k_gap, k_eq);  // always start from the local stiffness
  const VecX cap_gap = k_gap * options_.max_penalty_factor;
  const VecX cap_eq = k_eq * options_.max_penalty_factor;
  const double tol = penetration_tolerance(options_, p);
  const VecX zero_gap = VecX::Zero(p.num_gaps()), zero_eq = VecX::Zero(p.num_equalities());
  // One solver over the raises: its condensed K stays, a raise changes the surface block only;
  // each raise starts from the last one's sets.
  FrictionalSolver solver(p, memory);
  ConstraintSolution previous;
  s.status = SolveStatus::kMaxIterations;
  s.message = "penetration above tolerance after " + std::to_string(options_.max_iterations) +
              " stiffness raises";
  for (int round = 0; round < options_.max_iterations; ++round) {
    const int first = s.history.empty() ? 1 : s.history.back().iteration + 1;
    FrictionalOptions o = penalised_friction(set_rule(), p, memory, k_gap, zero_gap, k_eq, zero_eq);
    o.max_iterations = options_.max_iterations;
    o.first_iteration = first;
    if (round > 0) {
      previous = s;
      o.start = &previous;
    }
    solver.solve(o, s);
    s.penalty_history.push_back(std::max(k_gap.size() ? k_gap.maxCoeff() : 0.0,
                                         k_eq.size() ? k_eq.maxCoeff() : 0.0));
    if (s.status != SolveStatus::kConverged) break;
    const VecX g = p.gap0 + p.gap_jacobian * s.u;
    const VecX h = p.eq_jacobian * s.u - p.eq_rhs;
    bool raised = false, capped = false;
    for (int i = 0; i < g.size(); ++i)
      if (-g[i] > tol) {
        if (k_gap[i] >= cap_gap[i]) capped = true;
        else k_gap[i] = std::min(cap_gap[i], k_gap[i] * options_.penalty_growth), raised = true;
      }
    for (int j = 0; j < h.size(); ++j)
      if (std::abs(h[j]) > tol) {
        if (k_eq[j] >= cap_eq[j]) capped = true;
        else k_eq[j] = std::min(cap_eq[j], k_eq[j] * options_.penalty_growth), raised = true;
      }
    if (!raised && !capped) {
      s.status = SolveStatus::kConverged;
      s.message.clear();
      break;
    }
    if (!raised && capped) {
      s.status = SolveStatus::kMaxIterations;
      s.message = "penalty reached its cap (" + number_text(options_.max_penalty_factor) +
                  " x local stiffness) with penetration still above the tolerance";
      break;
    }
  }
  s.eq_penalty = k_eq;
  s.penalty = k_gap;
  return s;
}

}  // namespace c2d::constraints
