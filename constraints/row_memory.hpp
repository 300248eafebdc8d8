// What a method carries between its solves, per gap row of one ConstrainedProblem: where its
// sets and forces start, and what the load step keeps for its penalties. None of it is the
// problem (constrained_problem.hpp): a problem solved without memory is solved cold. The load
// step's outer iterations (nonlinear/contact_newton.cpp) fill it for each iterate and hand it
// to the method's solve (ConstraintStrategy::solve).
#pragma once

#include <vector>

#include "core/types.hpp"

namespace c2d::constraints {

/// Every field is optional: empty, or of another size than the problem's gap rows, is none given.
struct RowMemory {
  /// Warm start: the inequality rows to treat as closed at the start (none: the rows with
  /// g0 ≤ 0). A re-detection or a Newton iteration passes the previous active set.
  std::vector<char> initial_active;
  /// Warm start of the row forces λ. The augmented Lagrangian starts its multiplier iteration
  /// from it; with friction the first bounds come from it (the law's piece a frictional solve
  /// starts on, ipopt's first Tresca problem).
  VecX initial_force;
  /// Warm start of the friction states per row: 1 stick, 2 slip along +t, 3 slip along −t, 0
  /// none given (a closed row then starts sticking).
  std::vector<char> initial_friction;
  /// The friction force each row carried at the last converged state (the penalty's elastic
  /// tangential spring: its return map starts from it; none: 0).
  VecX tangent_force0;
  /// Each gap row's local stiffness to derive default penalties from (none: from K and G, see
  /// ConstrainedProblem::gap_local_stiffness). A load step keeps its first outer iteration's
  /// values, so its penalties do not drift with K_T and an outer iteration that changes no
  /// active set confirms the step instead of posing a slightly different problem.
  VecX gap_row_stiffness;
  /// How far the gaps may close in this solve: open rows whose gap is below it are likely to
  /// close (the first iterate of a load step: from how far the last step's contact grew; 0:
  /// unknown). A solve that condenses only the rows in play takes them in.
  double closing_reach = 0.0;
};

}  // namespace c2d::constraints
