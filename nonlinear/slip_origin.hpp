// Where each frictional row's slip starts in a load step (contact_newton.cpp): the method's
// history says which rows were closed at the step's start; the others slip from where the
// step's outer iterations first found them closed.
#pragma once

#include <vector>

#include "constraints/constrained_problem.hpp"
#include "constraints/constraint_strategy.hpp"
#include "constraints/contact_detection.hpp"

namespace c2d::nonlinear {

/// A row closed at the step's start slips from the last converged state, its friction force
/// there the start of a penalty's tangential spring. A row that was open slips from the state
/// of the outer iteration that first found it closed, with the friction force it held there
/// (a penalty's spring keeps its stretch): its slip while it was still approaching is not slip.
/// Without this, a node entering contact in a step was charged the step's whole tangential
/// motion (loading a Hertz contact with P and Q together made the newly touching edge nodes
/// slip, where the analysis has none). One per load step, over its outer iterations.
class SlipOrigin {
 public:
  explicit SlipOrigin(int slots) : slip_(slots, kNone), force_(slots, 0.0) {}

  /// Sets `qp`'s slip0 (given from the step's start) and `memory`'s tangent_force0 for its
  /// rows: `history` the method's at the step's start, `closed` the step's current set by slot,
  /// `tangent` the friction forces by slot of the step's last state (empty: none).
  void apply(const std::vector<constraints::GapRow>& rows, const constraints::StepHistory& history,
             const std::vector<char>& closed, const VecX& tangent,
             constraints::ConstrainedProblem& qp, constraints::RowMemory& memory);

 private:
  static constexpr double kNone = -1e300;  ///< not yet found closed in the step
  std::vector<double> slip_;   ///< per slot: its slip where first found closed
  std::vector<double> force_;  ///< and the friction force it held there
};

}  // namespace c2d::nonlinear
