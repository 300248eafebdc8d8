// The set a method starts an outer iteration from (contact_newton.cpp), and a body caught at
// first touch: what the step's memory and the rows' gaps say before the method has solved.
#pragma once

#include <vector>

#include "constraints/constrained_problem.hpp"
#include "constraints/constraint_strategy.hpp"
#include "constraints/contact_detection.hpp"

namespace c2d::nonlinear {

/// Warm start of `qp`'s rows in `memory` (their initial active set, friction states and
/// forces): the rows closed at the last state (`previous`, by slot: 0 open, 1 closed and
/// sticking, 2/3 slipping) with their forces `force_by_slot`, and the rows touching or
/// penetrating now. When nothing touches but some rows nearly do (within 1 % of the smallest
/// contact edge), the nearest are guessed closed.
void warm_start(const constraints::ConstrainedProblem& qp,
                const std::vector<constraints::GapRow>& rows, const std::vector<char>& previous,
                const std::vector<double>& force_by_slot, constraints::RowMemory& memory);

/// The strategy's solve of `qp` from `memory`; a body held only by its contact, caught at first
/// touch from farther than the warm start guesses, is singular with every row open, and one
/// touching a conformal surface at a node can be singular with that node's rows alone: then the
/// nearest open rows close (in `memory`'s initial active set; with some closed already, only
/// rows within 1 % of the smallest contact edge) and the strategy solves again, at most three
/// times (the active-set iteration opens them if the load says so). All the solves' work counts.
constraints::ConstraintSolution solve_catching_first_touch(
    constraints::ConstraintStrategy& strategy, const constraints::ConstrainedProblem& qp,
    constraints::RowMemory& memory);

}  // namespace c2d::nonlinear
