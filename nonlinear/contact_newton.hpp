// Contact inside a load step of the geometric-nonlinear analysis.
//
// A load step is a Newton iteration over the method's sets. Each iterate ("outer iteration")
//   1. detects the contact rows at the current configuration and linearises the problem there:
//      K_T with the contact's geometric stiffness under the state's forces (the first iterate
//      from an extrapolated start: the last converged state's) and the plates' (from the second
//      iterate on), the out-of-balance force, the gap and tangential rows. The first iterate
//      starts where the load stepper extrapolated the last increments to (a path that goes on
//      in proportion), else from the tangent predictor at the converged state;
//   2. hands it to the scene's ConstraintStrategy, which updates its active (and stick/slip)
//      sets on that problem and returns the step, forces and (penalty-type methods)
//      stiffnesses: friction on the condensed surface, one factorisation of K per iterate;
//   3. keeps the step when the residual at u + Δu, with the set held and the rows re-detected
//      there, is a tenth or less of the residual it set out to reduce (the larger of the last
//      state's and the state's with what the step holds: the method's new set, its new friction
//      forces), a Newton step; else continues the iterate with KINSOL with the set held (the
//      globalisation: penalty-type methods add the forces λ̂ − k g(u) of the active rows, exact
//      methods the multipliers of the active rows as unknowns) until the residual is that
//      tenth, and the method decides its set again from there (a method whose solve costs
//      more than two factorisations, such as ipopt: until KINSOL has converged). The active set
//      never changes inside a KINSOL solve, so its line search sees a smooth residual. Once an
//      attempt, a KINSOL solve that runs out of iterations or stalls after halving the residual
//      hands its state to the next iterate instead of failing the attempt (a node sliding past its
//      master's free end cannot keep the set it was held in).
// The step has converged when the strategy kept its set and the state, or the state its step
// reached, satisfies the equations with that set held; for a method that can recognise its
// solution in a state (ConstraintStrategy::state_test), also when the state KINSOL reached is
// one whose rows, detected afresh, that test's rule holds as held. A small-strain
// system takes the strategy's solution as it is (its rows are linear about the detection state)
// and confirms it by detecting again. `ipopt` is coupled the same way: Ipopt solves each iterate's
// QP.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "constraints/constraint_strategy.hpp"
#include "constraints/contact_set.hpp"
#include "core/results.hpp"
#include "nonlinear/contact_results.hpp"
#include "nonlinear/newton_solver.hpp"
#include "nonlinear/structural_system.hpp"

namespace c2d::nonlinear {

/// One outer iteration of a load step with contact.
struct ContactIteration {
  int outer = 0;
  int strategy_iterations = 0;  ///< the strategy's own iterations on the linearised problem
  SolveStatus strategy_status = SolveStatus::kConverged;
  double strategy_step = 0.0;   ///< ‖Δu‖∞ the strategy asked for
  int rows = 0, active = 0, entering = 0, leaving = 0;
  int stick = 0, slip = 0;      ///< friction: active rows sticking and slipping
  double penalty = 0.0;         ///< largest penalty stiffness in use (0: none)
  NewtonReport newton;          ///< KINSOL with the set fixed (no iterations: the step confirmed)
  int factorizations = 0;       ///< linear systems factorised: the strategy's and Newton's
  double max_penetration = 0.0; ///< after the KINSOL solve
  double max_force = 0.0;       ///< largest row force after the KINSOL solve
  double max_pressure = 0.0;    ///< largest recovered pressure then (0 without a slave surface)
};

/// What a converged state carries into the next load step: per row slot, 0 open, 1 closed (and
/// sticking, with friction), 2 closed and slipping along +t, 3 along −t.
using ContactMemory = std::vector<char>;

struct ContactStepInput {
  VecX u_free;          ///< converged free displacements of the previous step
  VecX u_prev_full;     ///< the same state as a full vector (previous prescribed values)
  /// Where the step's first iterate starts (free displacements): the last step's increment
  /// extrapolated. Empty: the tangent predictor from u_free (the prescribed increment lifted).
  VecX u_guess;
  NewtonOptions newton; ///< tolerance and limits; the residual scale is set per step
  double floor_scale = 0.0;  ///< smallest residual scale (stress-free, displacement-driven)
  int max_outer = 15;
  /// Every method step continued until it divides the residual by ten (the retry of an attempt
  /// whose sets cycled), instead of kept once it reduces it (constrained_step.hpp).
  bool strict = false;
};

/// The strategy's own work over a step's outer iterations: its iteration records (numbered on),
/// penalty raises, iterations, time and linear-solver figures, and the last solve's pivot ratio.
struct StrategyTotals {
  int iterations = 0, factorizations = 0, symbolic_analyses = 0;
  double seconds = 0, symbolic_seconds = 0, numeric_seconds = 0, solve_seconds = 0;
  double pivot_ratio = std::numeric_limits<double>::quiet_NaN();
  core::FactorInfo factor;  ///< the last factorisation's (ordering empty: none said)
  std::vector<constraints::IterationRecord> history;
  std::vector<double> penalty_history;
  void add(const constraints::ConstraintSolution& s);
  /// Another total's work (counts, times; its pivot ratio and factor when it has them), not
  /// its history.
  void add_work(const StrategyTotals& t);
};

struct ContactStepResult {
  SolveStatus status = SolveStatus::kFailed;
  std::string message;
  VecX u_free;
  /// The converged state's sets and friction forces by slot, for the method's history
  /// (ConstraintStrategy::step_accepted).
  constraints::StepHistory history;
  /// The method that finished the step after the outer iterations cycled or the step's own
  /// could not pose an iterate (ConstraintStrategy::fallback), and why; empty: the step's own
  /// method throughout.
  std::string fallback, fallback_reason;
  std::vector<ContactIteration> iterations;
  NewtonReport newton;  ///< the KINSOL solves of the step combined (iterations, norms)
  std::vector<constraints::GapRow> rows;   ///< at the converged state
  constraints::ConstraintSolution state;   ///< gaps, forces, active set, penalties there
  StrategyTotals strategy;                 ///< the strategy's solves over the outer iterations
  double detection_seconds = 0.0;          ///< contact search, every outer iteration
  /// Deepest penetration of the rows detected afresh at the final positions (not the
  /// linearised rows), and what a converged step allows: the penetration the method itself
  /// reports (a penalty's force / k) plus 1e-9 of the model size.
  /// NaN when the step ended before a state to measure.
  double measured_penetration = std::numeric_limits<double>::quiet_NaN();
  double penetration_tolerance = std::numeric_limits<double>::quiet_NaN();
  /// The deepest slave node below its master surface there (ContactSet::nodal_penetration).
  double nodal_penetration = std::numeric_limits<double>::quiet_NaN();
};

/// The constrained step: one load step to the load factor and prescribed values set on
/// `system` (finite or small strain), from the converged state in `in`. Every analysis with
/// contact passes through it, a linear one as a single step. Never throws for numerical
/// trouble; the caller keeps `in` as its snapshot. When the step fails, u_free, rows and state
/// hold the last trial state where one exists (a strategy that stopped at its iteration limit,
/// or the outer iteration cap), for a caller that reports it under the failed status.
ContactStepResult solve_contact_step(StructuralSystem& system,
                                     const constraints::ContactSet& contact,
                                     constraints::ConstraintStrategy& strategy,
                                     const ContactStepInput& in);

/// The smallest residual scale of a model: residuals are measured against the largest nodal
/// force in the system (load, reaction or contact force); a displacement-driven problem free of
/// stress falls back to the force of a 1e-6 strain on the smallest element edge.
double residual_floor_scale(const core::Model& model);


}  // namespace c2d::nonlinear
