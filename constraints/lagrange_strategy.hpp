// Lagrange multipliers with an active-set loop: the saddle-point system of the closed rows is
// solved by sparse LU; rows in tension leave, penetrating rows enter, until the set repeats.
#pragma once

#include "constraints/constraint_strategy.hpp"

namespace c2d::constraints {

class LagrangeStrategy final : public ConstraintStrategy {
 public:
  explicit LagrangeStrategy(const StrategyOptions& options) : options_(options) {}
  std::string name() const override { return "lagrange"; }

 protected:
  ConstraintSolution solve_problem(const ConstrainedProblem& problem) override;

 private:
  StrategyOptions options_;
};

}  // namespace c2d::constraints
