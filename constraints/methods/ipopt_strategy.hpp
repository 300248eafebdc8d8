// The contact problem as what it is, a convex QP (minimise the potential energy subject to the
// linearised non-penetration rows), handed to Ipopt with its exact sparse Hessian and Jacobian.
// Ipopt's multipliers are the contact forces. Rows are normalised to unit length, zero rows and
// duplicates are dropped before the solve (Ipopt's restoration failure usually means exactly
// such rows), and Ipopt's return codes map onto the common statuses.
#pragma once

#include "constraints/constraint_strategy.hpp"

namespace c2d::constraints {

class IpoptStrategy final : public ExactStrategy {
 public:
  using ExactStrategy::ExactStrategy;
  const SetRule& set_rule() const override { return rule_; }
  /// `lagrange`: the primal-dual active-set iteration that already confirms every set Ipopt
  /// finds (its crossover), on the whole step. Ipopt's problem is convex: where K_T is
  /// indefinite along a motion only the rows hold (a beam buckling against a cap), its dual
  /// holds that motion as if rigid, and the sets it finds at two linearisations can alternate
  /// where the exact active-set iteration settles.
  std::unique_ptr<ConstraintStrategy> fallback() const override;

 protected:
  ConstraintSolution solve_problem(const ConstrainedProblem& problem,
                                   const RowMemory& memory) override;

 private:
  PrimalDualRule rule_;
  /// Frictionless: propose each set from a loose interior point first, until the exact solves
  /// fail to confirm one (then the method's tolerance for the rest of the analysis).
  bool loose_first_ = true;
};

}  // namespace c2d::constraints
