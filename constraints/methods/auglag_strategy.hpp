// Augmented Lagrangian (Uzawa iteration on the multipliers): penalised subproblems with a
// moderate stiffness, the multipliers updated as λ ← max(0, λ − k g) until the penetration
// is below the tolerance. Exact in the limit without the ill-conditioning of a large penalty.
#pragma once

#include "constraints/constraint_strategy.hpp"
#include "constraints/set_rules.hpp"

namespace c2d::constraints {

class AugLagStrategy final : public RegularisedStrategy {
 public:
  using RegularisedStrategy::RegularisedStrategy;
  /// Its rounds converge to the exact solution (the estimates λ̂ to the state's forces), so a
  /// state is judged as an exact method's would be: the primal-dual rule on its forces, gaps and
  /// slips, with the penetration within the method's tolerance. Its own return map cannot judge
  /// a state (it reads λ̂, which each round moves): without this, a frictional step whose Newton
  /// state and exact solve disagree by a stick row's spring (Newton holds stick rows as springs
  /// about λ̂) alternated between the two until the step was cut back (a pin in a plate's hole:
  /// 55 factorisations for 6 steps, 17 for 4 with the test).
  StateTest state_test(const ConstrainedProblem& p) const override;

 protected:
  ConstraintSolution solve_problem(const ConstrainedProblem& problem,
                                   const RowMemory& memory) override;
  bool augmented() const override { return true; }

 private:
  PrimalDualRule state_rule_;
};

}  // namespace c2d::constraints
