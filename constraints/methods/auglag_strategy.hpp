// Augmented Lagrangian (Uzawa iteration on the multipliers): penalised subproblems with a
// moderate stiffness, the multipliers updated as λ ← max(0, λ − k g) until the penetration
// is below the tolerance. Exact in the limit without the ill-conditioning of a large penalty.
#pragma once

#include "constraints/constraint_strategy.hpp"

namespace c2d::constraints {

class AugLagStrategy final : public RegularisedStrategy {
 public:
  using RegularisedStrategy::RegularisedStrategy;

 protected:
  ConstraintSolution solve_problem(const ConstrainedProblem& problem,
                                   const RowMemory& memory) override;
  bool augmented() const override { return true; }
};

}  // namespace c2d::constraints
