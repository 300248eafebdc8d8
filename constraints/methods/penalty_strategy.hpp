// Penalty: each closed gap row becomes a spring of stiffness k; the constraint holds only up to
// a penetration of about force / k, which the solution reports. The active set is the rows with
// g < 0 at the solved state; when that iteration wanders, the dual active-set safeguard finishes.
#pragma once

#include "constraints/constraint_strategy.hpp"
#include "constraints/friction_solver.hpp"

namespace c2d::constraints {

class PenaltyStrategy final : public RegularisedStrategy {
 public:
  using RegularisedStrategy::RegularisedStrategy;
  /// Its own rule on a frictionless state (its force −k g, λ̂ = 0: held where g < 0); with
  /// friction none, as the return map's tangential trial needs estimates a state does not carry.
  StateTest state_test(const ConstrainedProblem& p) const override {
    return p.has_friction() ? StateTest{} : StateTest{&set_rule()};
  }

 protected:
  ConstraintSolution solve_problem(const ConstrainedProblem& problem,
                                   const RowMemory& memory) override;
};

/// Penalty stiffness per gap row and per equality row: the input's fixed k where it gives one,
/// else `absolute_k` when > 0, else factor × the row's local stiffness (a gap row's as `memory`
/// kept it, ConstrainedProblem::gap_local_stiffness).
void default_penalties(const ConstrainedProblem& p, const RowMemory& memory, double absolute_k,
                       double factor, VecX& k_gap, VecX& k_eq);

/// The frictional solve of a penalised problem (friction_solver.hpp) with these stiffnesses and
/// multiplier estimates; k_t = the rows' tangential ratio × k, λ̂_t = the memory's
/// tangent_force0 (the last converged state's friction force; 0 without one).
FrictionalOptions penalised_friction(const SetRule& rule, const ConstrainedProblem& p,
                                     const RowMemory& memory, const VecX& k_gap, const VecX& lambda,
                                     const VecX& k_eq, const VecX& mu);

}  // namespace c2d::constraints
