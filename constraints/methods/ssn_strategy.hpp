// Semi-smooth Newton on the complementarity function C(λ, g) = λ − max(0, λ − c g) (the
// primal-dual active set method of Hintermüller, Ito and Kunisch): all rows stay in one
// saddle-point system whose pattern never changes, so UMFPACK's symbolic analysis is done once
// and each iteration is one numeric factorization. Converges in a few steps to the exact
// solution. Globalised by the dual active-set safeguard (strategy_common.hpp): a step that
// returns to an earlier set or stops reducing the rows that change hands over to it, and its
// dual objective grows monotonically until the complementarity conditions hold.
#pragma once

#include "constraints/constraint_strategy.hpp"

namespace c2d::constraints {

class SsnStrategy final : public ExactStrategy {
 public:
  using ExactStrategy::ExactStrategy;
  const SetRule& set_rule() const override { return rule_; }

 protected:
  ConstraintSolution solve_problem(const ConstrainedProblem& problem,
                                   const RowMemory& memory) override;

 private:
  SemiSmoothRule rule_;
};

}  // namespace c2d::constraints
