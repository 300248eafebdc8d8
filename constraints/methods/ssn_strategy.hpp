// Semi-smooth Newton on the complementarity function C(λ, g) = λ − max(0, λ − c g) (the
// primal-dual active set method of Hintermüller, Ito and Kunisch): all rows stay in one
// saddle-point system whose pattern never changes, so UMFPACK's symbolic analysis is done once
// and each iteration is one numeric factorization. Converges in a few steps to the exact
// solution; a returning active set is reported as cycling.
#pragma once

#include "constraints/constraint_strategy.hpp"

namespace c2d::constraints {

class SsnStrategy final : public ExactStrategy {
 public:
  using ExactStrategy::ExactStrategy;

 protected:
  ConstraintSolution solve_problem(const ConstrainedProblem& problem) override;
};

}  // namespace c2d::constraints
