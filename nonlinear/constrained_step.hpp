// One load step's outer iterations (contact_newton.hpp describes the loop), shared by the
// two files that define them: contact_newton.cpp (the iterate: linearise, ask the method, keep
// its set and state) and held_set_newton.cpp (Newton with the method's set held: whether a state
// satisfies the equations, KINSOL's globalisation, the state it keeps). Internal to nonlinear/.
#pragma once

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "constraints/active_set_tracker.hpp"
#include "nonlinear/active_set_system.hpp"
#include "nonlinear/contact_newton.hpp"
#include "nonlinear/slip_origin.hpp"

namespace c2d::nonlinear {

/// One load step's outer iterations (see contact_newton.hpp), as named steps over the state
/// they share: the current free displacements, the active set by slot, the last solve's row
/// forces, and the last state that satisfied the equations with its set held.
class ConstrainedStep {
  using ActiveSetTracker = constraints::ActiveSetTracker;
  using ConstrainedProblem = constraints::ConstrainedProblem;
  using ConstraintSolution = constraints::ConstraintSolution;
  using ConstraintStrategy = constraints::ConstraintStrategy;
  using ContactSet = constraints::ContactSet;
  using GapRow = constraints::GapRow;
  using RowMemory = constraints::RowMemory;

 public:
  ConstrainedStep(StructuralSystem& system, const ContactSet& contact, ConstraintStrategy& strategy,
                  const ContactStepInput& in);
  ContactStepResult run();

 private:
  /// One outer iteration; false when the step failed (out_ says why), out_.status converged
  /// when it ended the step.
  bool iterate(int outer);
  /// The method solving the step's iterates: the step's own, or its fallback.
  ConstraintStrategy& method() const { return fallback_ ? *fallback_ : strategy_; }
  /// Hands this iterate and the rest of the step to the method's fallback, for `reason` (the
  /// report's fallback_reason); false when the method has none or has already handed over.
  bool hand_to_fallback(const std::string& reason);
  /// The method's solve of the linearised problem `qp` (constants `c`) from memory_, its work
  /// and set in the iteration record `it`; `next` its active set by slot. False when it failed:
  /// its trial state kept, the step failed with its status.
  bool solve_method(const ConstrainedProblem& qp, const VecX& c, ContactIteration& it,
                    ConstraintSolution& s, ContactMemory& next);
  /// The stiffness the strategy linearises with: K_T and the rows' curvature under the state's
  /// forces (the contact's geometric stiffness, as Newton's Jacobian has it; in the first outer
  /// iteration, from an extrapolated start, under the last converged state's forces), and from
  /// the second outer iteration on the plates', so that the strategy's step is a Newton step.
  SpMat tangent(int outer, const VecX& u_full) const;
  /// The out-of-balance force and tangent at u_full (outer iterations after the first).
  bool linearise(const VecX& u_full, VecX& load);
  /// The rows detected now are those of the kept state (same slave nodes); the closed ones have
  /// the gaps its linearisation predicted (a node sliding along a flat master changes edge, not
  /// gap) and the open ones do not penetrate. An open row's gap need not match its
  /// linearisation (a node passing a free master end turns its normal): it carries no force.
  bool reproduces_state() const;
  /// The rows' local stiffness (the base of default penalties) as the step first met each slot,
  /// into memory_.
  void keep_local_stiffness(const ConstrainedProblem& qp);
  /// The strategy's figures in the iteration record; returns its active set by slot.
  ContactMemory record_strategy(const ConstrainedProblem& qp, const ConstraintSolution& s,
                                ContactIteration& it) const;
  /// A strategy that stopped short (iteration limit, cycle, ill-conditioning) leaves its
  /// trial state for a caller that reports it as such.
  void keep_partial(const VecX& c, const ConstrainedProblem& qp, const ConstraintSolution& s);
  /// KINSOL with the set fixed, from the strategy's step when the set changed, from the state
  /// itself (and its own multipliers) when the strategy kept it; no solve when the start
  /// already satisfies the equations. False when Newton failed.
  bool hold_set(const ConstrainedProblem& qp0, const VecX& c0, const ConstraintSolution& s0,
                bool same_set, ContactIteration& it);
  /// The held rows' forces: the strategy's (`step`) and the state's own (`state`: the previous
  /// solve's; a row entering now carries none).
  struct HeldForces {
    const VecX& step;
    const VecX& state;
  };
  /// Finite strain: whether the method's step x already satisfies the equations as now held
  /// (then, with the set kept, the step has converged), or reduced the residual it set out
  /// from enough to be the next iterate; else Newton with the set held continues it. `norm`
  /// holds the state's residual when the set was kept, and x's after; `satisfied_now` whether x
  /// satisfies the held equations. False when Newton failed.
  bool finite_strain_step(ActiveSetSystem& sys, VecX& x, const NewtonOptions& newton,
                          ContactIteration& it, const HeldForces& forces,
                          const ConstraintSolution& s0, const ConstraintSolution& s, bool same_set,
                          double& norm, bool& satisfied_now);
  /// Whether the method's state test (ConstraintStrategy::state_test) recognises the state just
  /// kept as its solution: its penetration within the test's, and the test's rule keeping the
  /// set it was solved with: the rows detected afresh there, each held slot still a row that the
  /// rule holds (compressive), every other row one it leaves open (not penetrating), and with
  /// friction each sticking row within its bound, each slipping row slipping along its force
  /// with that force at the bound of its normal force to `tolerance`. Not Tresca's rows, which
  /// carry friction open.
  bool settled(const ConstrainedProblem& qp, double tolerance) const;
  /// Whether x already satisfies the equations. A gap detected from absolute coordinates
  /// carries their round-off, ε·|x|, which a row stiffness k turns into a force of k·ε·|x|:
  /// with penalties 1e3 times the element stiffness that floor can exceed the tolerance, so it
  /// bounds the test from below.
  bool satisfied(ActiveSetSystem& sys, const VecX& x, const NewtonOptions& newton,
                 ContactIteration& it, double& norm) const;
  /// The residual a state must reach to satisfy the equations with the set held: the Newton
  /// test, never below the residual's round-off floor.
  double tolerance(const ActiveSetSystem& sys, const NewtonOptions& newton) const;
  /// An iterate's Newton work (its factorisations, iterations, norms) into the step's.
  void add_newton(ContactIteration& it);
  /// The residual's round-off floor with the set held: a gap's round-off, ε·|x|, times the
  /// stiffest row.
  double round_off_floor(const ActiveSetSystem& sys) const;
  /// KINSOL with the set held from x; false when it failed (out_ says why). With
  /// `from_method_step`, x is the method's step, counted as that Newton's first iteration.
  /// With `may_continue`, true also where it handed an unconverged state on (see below:
  /// it.newton.status says so). Newton stops at a residual of `enough` when that is above the
  /// test: the set it holds was decided at a state far from this one, and the method decides
  /// it again once Newton is back in its quadratic range (the state's residual divided by
  /// ten), rather than after Newton has converged with a set that may be about to change.
  bool newton_with_set_held(ActiveSetSystem& sys, VecX& x, const NewtonOptions& options,
                            ContactIteration& it, bool from_method_step, bool may_continue = false,
                            double enough = 0.0);
  /// The held state: `stick` lists the sticking rows held after the equality rows.
  void keep_state(ActiveSetSystem& sys, const VecX& x, const ConstraintSolution& s,
                  ContactIteration& it, const std::vector<int>& stick);
  /// "converged" is checked on the final state: the rows detected afresh at the final
  /// positions (paired there; a linear run's gaps linearised as its analysis is) may not
  /// penetrate beyond what the method reports. Each slave node's depth below the deformed
  /// master surface, in the final geometry, is measured beside it. A failed step is measured too.
  void verify_final_state();
  void fail(SolveStatus status, const std::string& message);

  static double inf_norm(const VecX& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }
  /// An exact method's step is kept as the next iterate when it reduces the residual to this
  /// fraction of the one it set out from (a sufficient decrease: the method decides its set
  /// again from there); a slower one is continued by Newton with the set held, whose rows
  /// follow the iterate (a node sliding onto the next master edge), until it has. Hard cases
  /// (90 runs): lagrange and ssn 707 -> 559 factorisations, ipopt 882 -> 734 against 0.1.
  static constexpr double kStepDecrease = 0.9;
  /// The regularised methods' (their sets decided at a far state cycled at a penalised
  /// frictional first touch, and T3 slides were cut back), and any method's in the attempt the
  /// load stepper makes again after one whose sets cycled (ContactStepInput::strict): each
  /// step must divide the residual by ten.
  static constexpr double kStrictStepDecrease = 0.1;
  /// Factorisations a strategy's solve may cost for its step to be kept that way.
  static constexpr int kCheapStrategy = 2;

  StructuralSystem& system_;
  const ContactSet& contact_;
  ConstraintStrategy& strategy_;
  std::unique_ptr<ConstraintStrategy> fallback_;  ///< the method's fallback, once called on
  const ContactStepInput& in_;
  VecX u_;
  ContactMemory previous_;
  ActiveSetTracker sets_;  ///< the sets by slot of the outer iterations (cycle detection)
  std::vector<double> force_by_slot_;  ///< the last solve's row forces
  VecX tangent_by_slot_;               ///< friction: the held state's friction forces
  SlipOrigin slip_origin_;             ///< friction: where each row's slip starts in the step
  /// What the method carries into its solve of the current iterate's problem, per row: the
  /// warm start, the friction forces its springs start from, the kept local stiffness.
  RowMemory memory_;
  /// The largest gap (at its linearisation point) of a row that closed in this step's solves:
  /// the history's closing_reach.
  double closing_reach_ = 0.0;
  /// The next step's first iterate takes open rows within this multiple of it as likely to
  /// close (on a slender beam pressed on a floor the reach shrinks step by step, 3.3e-3,
  /// 9.1e-4, 4.2e-4, ...; a Hertz contact grows as √P).
  static constexpr double kReachMargin = 1.5;
  const double step_decrease_;  ///< kStepDecrease, or kStrictStepDecrease (in.strict, regularised)
  std::vector<double> local_by_slot_;  ///< each slot's local stiffness, as first met (0: not yet)
  double step_scale_ = 0.0;            ///< the largest residual scale of the step so far
  bool continued_ = false;             ///< a held solve that did not converge handed its state on
  /// The residual a method's step must divide by ten to be kept as a Newton step: the larger
  /// of the last state's and the state's residual with what the step holds (∞ before the first).
  double last_norm_ = std::numeric_limits<double>::infinity();
  double coordinate_scale_ = 0.0;  ///< the lengths a gap is computed from, for round-off
  double absolute_scale_ = 0.0;    ///< the coordinates' size (gaps from absolute positions)
  double displacement_scale_ = 0.0;  ///< the step's starting displacements' size, ‖u‖∞
  bool from_guess_ = false;  ///< the first iterate started from the stepper's extrapolation
  std::vector<GapRow> rows_, state_rows_;
  ConstraintSolution state_;
  std::string where_;
  ContactStepResult out_;
};

}  // namespace c2d::nonlinear
