// Adaptive penalty: the seed's hand procedure (raise the gap stiffness until nothing
// penetrates) made automatic. Each row starts at its local element stiffness; a row whose
// penetration exceeds the tolerance has its k multiplied by a growth factor, up to a cap.
#pragma once

#include "constraints/constraint_strategy.hpp"

namespace c2d::constraints {

class AdaptivePenaltyStrategy final : public ConstraintStrategy {
 public:
  explicit AdaptivePenaltyStrategy(const StrategyOptions& options) : options_(options) {}
  std::string name() const override { return "adaptive_penalty"; }

 protected:
  ConstraintSolution solve_problem(const ConstrainedProblem& problem) override;

 private:
  StrategyOptions options_;
};

}  // namespace c2d::constraints
