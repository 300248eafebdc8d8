// The one set engine's rules (issue 33, item 3): how a method chooses the next normal and
// tangential state of each row from a solve. The one set iteration, FrictionalSolver
// (friction_solver.hpp), solves every method's problems, with and without friction, and asks
// the method's rule; it never switches on the method.
//
// A rule reads one row at a time (RowSolution: its force, gap, tangential force and slip, its
// state in the solve, its penalties and estimates when the method regularises it) and returns
// the row's next states. Three rules cover the six methods:
//   primal-dual (lagrange, ipopt's crossover): a held row stays unless λ < 0, a free row enters
//       when g < 0; a stick row slips when |λ_t| exceeds the bound, a slipping row sticks when
//       its slip turns against its force;
//   semi-smooth (ssn): held iff λ − c g > 0, then stick iff |λ_t + c s| ≤ bound (Hüeber,
//       Stadler and Wohlmuth, SISC 2008; c a stiffness), else slip along λ_t + c s. Where its
//       sets return to an earlier combination it continues with the primal-dual rule, its
//       limit c → 0, which moves one decision at a time (on_cycle());
//   return map (penalty, adaptive_penalty, auglag): held iff the trial force λ̂ − k g > 0, then
//       stick iff |λ̂_t + k_t s| ≤ bound, else slip; a slipping row whose trial force turns
//       against its slip passes through stick.
// Within a round-off margin of the bound a row keeps its tangential state, so the sets cannot
// chatter on it.
#pragma once

namespace c2d::constraints {

/// A row's tangential state in a set iteration.
enum Tangential : char { kFree = 0, kStick = 1, kSlipPlus = 2, kSlipMinus = 3 };

/// What a rule reads of one row after a solve (forces compressive positive).
struct RowSolution {
  double force = 0.0;          ///< λ
  double gap = 0.0;            ///< g
  double tangent_force = 0.0;  ///< λ_t
  double slip = 0.0;           ///< s
  bool held = false;           ///< the normal row was held in the solve
  char tangential = kFree;     ///< its tangential state in the solve
  bool closable = true;        ///< it has coefficients (a row on prescribed DOFs cannot close)
  /// A regularised row's stiffnesses and multiplier estimates (the return map's λ̂ − k g).
  double penalty = 0.0, tangent_penalty = 0.0;
  double force_estimate = 0.0, tangent_estimate = 0.0;
  /// The slip an entering row may have and still stick (the primal-dual rule's μ|g|, Tresca's
  /// round-off): the limit c → 0 of the semi-smooth rule's |c s| ≤ μ c |g|.
  double entry_slip_allowance = 0.0;
};

/// The scales a rule compares with: round-off margins of forces and gaps, and the semi-smooth
/// rule's c (a stiffness, so that λ − c g compares a force with a force).
struct RuleScales {
  double force_tolerance = 0.0;
  double gap_tolerance = 0.0;
  double c = 1.0;
};

/// A row's next normal state.
struct NormalDecision {
  bool held = false;
  double normal = 0.0;    ///< the normal force the friction bound is taken at
  double trial_t = 0.0;   ///< the tangential force the stick/slip decision compares
  double residual = 0.0;  ///< the row's violation of the normal complementarity (a force)
};

class SetRule {
 public:
  virtual ~SetRule() = default;
  virtual const char* name() const = 0;
  /// Whether the method regularises its rows (compliant rows, λ = λ̂ − k g when held).
  virtual bool regularised() const { return false; }
  virtual NormalDecision normal(const RowSolution& r, const RuleScales& s) const = 0;
  /// The next tangential state of a row that carries friction, given its normal decision and
  /// the bound at that decision's normal force; raises `residual` to the row's violation of
  /// the tangential conditions.
  virtual char tangential(const RowSolution& r, const NormalDecision& d, double bound,
                          const RuleScales& s, double& residual) const = 0;
  /// The rule that continues where this one's sets cycle, or null (a cycle is then the
  /// caller's to handle).
  virtual const SetRule* on_cycle() const { return nullptr; }
};

class PrimalDualRule final : public SetRule {
 public:
  const char* name() const override { return "primal-dual"; }
  NormalDecision normal(const RowSolution& r, const RuleScales& s) const override;
  char tangential(const RowSolution& r, const NormalDecision& d, double bound,
                  const RuleScales& s, double& residual) const override;
};

class SemiSmoothRule final : public SetRule {
 public:
  const char* name() const override { return "semi-smooth"; }
  NormalDecision normal(const RowSolution& r, const RuleScales& s) const override;
  char tangential(const RowSolution& r, const NormalDecision& d, double bound,
                  const RuleScales& s, double& residual) const override;
  const SetRule* on_cycle() const override { return &fallback_; }

 private:
  PrimalDualRule fallback_;
};

class ReturnMapRule final : public SetRule {
 public:
  const char* name() const override { return "return map"; }
  bool regularised() const override { return true; }
  NormalDecision normal(const RowSolution& r, const RuleScales& s) const override;
  char tangential(const RowSolution& r, const NormalDecision& d, double bound,
                  const RuleScales& s, double& residual) const override;
};

}  // namespace c2d::constraints
