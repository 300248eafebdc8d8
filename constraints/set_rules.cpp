#include "constraints/set_rules.hpp"

#include <algorithm>
#include <cmath>

namespace c2d::constraints {

namespace {

/// The stick/slip decision of the rules that compare a trial force with the bound: slip along
/// the trial force above the bound, stick below it, keep the state within round-off of it.
char trial_state(const RowSolution& r, double trial_t, double bound, const RuleScales& s,
                 double& residual) {
  const double excess = std::abs(trial_t) - bound;
  char next = r.tangential;
  if (excess > s.force_tolerance)
    next = trial_t > 0 ? kSlipPlus : kSlipMinus;
  else if (excess < -s.force_tolerance || r.tangential == kFree)
    next = kStick;
  if (next == kSlipPlus || next == kSlipMinus)
    residual = std::max(residual, std::abs(r.tangent_force - (trial_t > 0 ? bound : -bound)));
  return next;
}

/// A slipping row whose trial force turns against its slip passes through stick. A trial
/// compared with the bound alone can flip such a row between the two slip directions for ever
/// (the return map), or send every row of a body that may turn into slip along one rigid turn
/// that only K_T resists (the semi-smooth trial λ_t + c s with c the mean diagonal of K: a pin
/// in a hole at the first step of a tangential load). At a solution a slipping row's trial
/// points along its force, so the guard never holds a converged set.
bool turns_against_its_slip(const RowSolution& r, double trial_t) {
  return (r.tangential == kSlipPlus && trial_t < 0) || (r.tangential == kSlipMinus && trial_t > 0);
}

}  // namespace

NormalDecision PrimalDualRule::normal(const RowSolution& r, const RuleScales& s) const {
  NormalDecision d;
  d.held = r.held ? r.force >= -s.force_tolerance : r.closable && r.gap < -s.gap_tolerance;
  d.normal = r.force;
  d.trial_t = r.tangent_force;
  d.residual = r.held ? std::max(0.0, -r.force) : 0.0;
  return d;
}

char PrimalDualRule::tangential(const RowSolution& r, const NormalDecision&, double bound,
                                const RuleScales& s, double& residual) const {
  // A stick row slips when its force exceeds the bound; a slipping row sticks when its slip
  // turns against its force; a row that enters (λ = λ_t = 0, g < 0) slips along its slip when
  // that exceeds its allowance, else sticks.
  char next = r.tangential;
  if (r.tangential == kStick && std::abs(r.tangent_force) > bound + s.force_tolerance)
    next = r.tangent_force > 0 ? kSlipPlus : kSlipMinus;
  else if ((r.tangential == kSlipPlus && r.slip < -s.gap_tolerance) ||
           (r.tangential == kSlipMinus && r.slip > s.gap_tolerance))
    next = kStick;
  else if (r.tangential == kFree)
    next = std::abs(r.slip) > r.entry_slip_allowance ? (r.slip > 0 ? kSlipPlus : kSlipMinus)
                                                     : kStick;
  if (r.tangential == kStick) residual = std::max(residual, std::abs(r.tangent_force) - bound);
  return next;
}

NormalDecision SemiSmoothRule::normal(const RowSolution& r, const RuleScales& s) const {
  NormalDecision d;
  d.normal = r.force - s.c * r.gap;
  d.held = r.closable && d.normal > s.force_tolerance;
  d.trial_t = r.tangent_force + s.c * r.slip;
  d.residual = std::abs(r.force - std::max(0.0, d.normal));
  return d;
}

char SemiSmoothRule::tangential(const RowSolution& r, const NormalDecision& d, double bound,
                                const RuleScales& s, double& residual) const {
  if (turns_against_its_slip(r, d.trial_t)) return kStick;
  return trial_state(r, d.trial_t, bound, s, residual);
}

NormalDecision ReturnMapRule::normal(const RowSolution& r, const RuleScales&) const {
  NormalDecision d;
  d.normal = r.force_estimate - r.penalty * r.gap;
  d.held = d.normal > 0;
  d.trial_t = r.tangent_estimate + r.tangent_penalty * r.slip;
  return d;
}

char ReturnMapRule::tangential(const RowSolution& r, const NormalDecision& d, double bound,
                               const RuleScales& s, double& residual) const {
  if (turns_against_its_slip(r, d.trial_t)) return kStick;
  return trial_state(r, d.trial_t, bound, s, residual);
}

}  // namespace c2d::constraints
