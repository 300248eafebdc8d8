// Lagrange multipliers with an active-set loop: the saddle-point system of the closed rows is
// solved by sparse LU; rows in tension leave, penetrating rows enter, until the set repeats.
// A set that cycles or stops settling (a slender body pushed onto one point) is finished by the
// dual active-set safeguard (strategy_common.hpp), whose states never carry tension.
#pragma once

#include "constraints/constraint_strategy.hpp"

namespace c2d::constraints {

class LagrangeStrategy final : public ExactStrategy {
 public:
  using ExactStrategy::ExactStrategy;
  const SetRule& set_rule() const override { return rule_; }

 protected:
  ConstraintSolution solve_problem(const ConstrainedProblem& problem,
                                   const RowMemory& memory) override;

 private:
  PrimalDualRule rule_;
};

}  // namespace c2d::constraints
