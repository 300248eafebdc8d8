// Friction in the Newton solve of an outer iteration (contact_newton.cpp): which of the method's
// frictional rows Newton holds, and how.
#pragma once

#include <vector>

#include "constraints/constrained_problem.hpp"
#include "core/types.hpp"

namespace c2d::nonlinear {

/// Friction in a Newton solve with the set held: the sticking rows become held rows, appended to
/// the equality rows as c = −s(u) (their multiplier, or their tangential spring λ̂_t + k_t s, is
/// the friction force, so a body held sideways by friction alone is held in Newton too); the
/// slipping rows' forces stay at the method's values, a fixed force −Tᵀλ_t.
struct HeldFriction {
  std::vector<int> stick;  ///< the sticking gap rows
  constraints::ConstrainedProblem qp;   ///< the problem with their rows appended to the equality rows
  constraints::ConstraintSolution s;    ///< the solution with their forces (and tangential stiffness)
  VecX c;                  ///< the held rows' constants, theirs appended
  VecX fixed_force;        ///< −T_slipᵀ λ_t on the free DOFs

  /// `u` is the state the problem was linearised at (qp's rows are in terms of the step).
  HeldFriction(const constraints::ConstrainedProblem& p, const VecX& c0,
               const constraints::ConstraintSolution& sol, const VecX& u);
};

}  // namespace c2d::nonlinear
