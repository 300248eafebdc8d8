// Adaptive penalty: the seed's hand procedure (raise the gap stiffness until nothing
// penetrates) made automatic. Each row starts at its local element stiffness; a row whose
// penetration exceeds the tolerance has its k multiplied by a growth factor, up to a cap.
#pragma once

#include "constraints/constraint_strategy.hpp"

namespace c2d::constraints {

class AdaptivePenaltyStrategy final : public RegularisedStrategy {
 public:
  using RegularisedStrategy::RegularisedStrategy;

 protected:
  ConstraintSolution solve_problem(const ConstrainedProblem& problem,
                                   const RowMemory& memory) override;
};

}  // namespace c2d::constraints
