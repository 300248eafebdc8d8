// Newton with the method's set held: the second half of a load step's outer iteration
// (constrained_step.hpp). Whether a state satisfies the equations with the set held, KINSOL as
// the globalisation when the method's step did not divide the residual by ten, and the state an
// iterate keeps.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

#include "constraints/strategy_common.hpp"
#include "nonlinear/constrained_step.hpp"
#include "nonlinear/held_friction.hpp"

namespace c2d::nonlinear {

using namespace c2d::constraints;

bool ConstrainedStep::hold_set(const ConstrainedProblem& qp0, const VecX& c0,
                               const ConstraintSolution& s0, bool same_set, ContactIteration& it) {
  std::unique_ptr<HeldFriction> friction;
  if (s0.friction_state.size() == static_cast<size_t>(qp0.num_gaps()) && qp0.num_gaps() > 0)
    friction = std::make_unique<HeldFriction>(qp0, c0, s0, u_);
  const ConstrainedProblem& qp = friction ? friction->qp : qp0;
  const ConstraintSolution& s = friction ? friction->s : s0;
  const VecX& c = friction ? friction->c : c0;
  const int m = qp.num_gaps(), me = qp.num_equalities();
  // The held rows: the gap rows, then the equality rows (their forces: the multipliers μ).
  VecX step_force(m + me);  // the strategy's (terms whose forces follow from u ignore them)
  step_force << s.contact_force, s.eq_multiplier;
  // The state's own forces on the held rows (the previous solve's; a row entering now: 0).
  VecX state_force = step_force;
  for (int i = 0; i < m; ++i) state_force[i] = force_by_slot_[rows_[i].slot];
  const int me0 = qp0.num_equalities();
  if (state_.eq_multiplier.size() == me0) state_force.segment(m, me0) = state_.eq_multiplier;
  std::vector<char> held = s.active;
  held.resize(m + me, 1);
  ActiveSetSystem sys(system_, contact_, rows_, stack_rows(qp.gap_jacobian, qp.eq_jacobian), c,
                      method().active_set_terms(qp, s), held,
                      friction ? static_cast<int>(friction->stick.size()) : 0);
  if (friction) sys.set_fixed_force(friction->fixed_force);
  // A penalty-type method's forces follow the iterate's gaps times k; their curvature terms
  // are weighed with at most the method's own forces (exact methods' multipliers are
  // unknowns of the solve, and no k amplifies their gaps).
  if (!method().exact()) sys.bound_curvature_forces(step_force.cwiseAbs());
  VecX x = sys.pack(same_set ? u_ : VecX(u_ + s.u), same_set ? state_force : step_force);
  NewtonOptions newton = in_.newton;
  // The force scale of the step's residuals: the largest met in the step, so that the state
  // a solve converged to is judged by the same measure when the next outer iteration checks it.
  newton.residual_scale =
      std::max({newton.residual_scale, inf_norm(s.contact_force), inf_norm(s.eq_multiplier),
                system_.reaction_scale(x.head(u_.size())), in_.floor_scale, step_scale_});
  step_scale_ = newton.residual_scale;
  // The step: the strategy's solve of the problem linearised at u is a Newton step with the
  // sets updated. The step ends where the method kept its set at u and the state already
  // satisfies the equations with that set held, or its step reached such a state. A step
  // that does not divide the residual by ten is continued by Newton with the set held
  // (KINSOL, line search), the globalisation, until it has (newton_with_set_held's `enough`).
  double norm = 0.0;
  bool satisfied_now = false;  // x satisfies the equations with the set held
  if (same_set && satisfied(sys, x, newton, it, norm)) {
    out_.status = SolveStatus::kConverged;
  } else if (system_.is_linear()) {
    // Small strain: the strategy's solution solves the rows it was given, linear about the
    // detection state; Newton only where the state does not satisfy them (the next outer
    // iteration detects again and confirms).
    if (!satisfied(sys, x, newton, it, norm) &&
        !newton_with_set_held(sys, x, newton, it, !same_set))
      return false;
  } else if (!finite_strain_step(sys, x, newton, it, {step_force, state_force}, s0, s, same_set,
                                 norm, satisfied_now)) {
    return false;
  }
  last_norm_ = it.newton.final_residual;
  u_ = x.head(u_.size());
  keep_state(sys, x, s0, it, friction ? friction->stick : std::vector<int>());
  // A state that satisfies the equations with its set held, where the method's rule keeps
  // that set, ends the step: asking the method again would factorise only to confirm.
  if (satisfied_now && out_.status != SolveStatus::kConverged &&
      settled(qp0, tolerance(sys, newton)))
    out_.status = SolveStatus::kConverged;
  out_.iterations.push_back(it);
  return true;
}

bool ConstrainedStep::finite_strain_step(ActiveSetSystem& sys, VecX& x, const NewtonOptions& newton,
                                         ContactIteration& it, const HeldForces& forces,
                                         const ConstraintSolution& s0, const ConstraintSolution& s,
                                         bool same_set, double& norm, bool& satisfied_now) {
  const VecX& step_force = forces.step;
  const VecX& state_force = forces.state;
  // The step is a Newton step of the equations as now held (the method's set, its
  // friction forces), so the residual it must reduce is theirs at the state it started
  // from, with the state's forces (a row entering carries none yet, a leaving one none any
  // more). It can be far above the last state's residual with what was held then: a state
  // Newton converged with one row too many is out of balance by that row's force once the
  // row is gone, and one converged with the slipping rows' forces held is out of balance
  // by their change once the method has updated them. The first iterate of the step: its
  // residual before the step, with the method's forces.
  double before = norm;  // same set: the state's residual, measured above
  if (!same_set) {
    VecX r;
    const bool first = !std::isfinite(last_norm_);
    before = sys.residual(sys.pack(u_, first ? step_force : state_force), r)
                 ? inf_norm(r)
                 : std::numeric_limits<double>::quiet_NaN();
  }
  if (std::isfinite(before))
    last_norm_ = std::isfinite(last_norm_) ? std::max(last_norm_, before) : before;
  if (same_set) x = sys.pack(VecX(u_ + s.u), step_force);
  // Finite strain: the held rows are detected again at x, so a state that satisfies them
  // with the set the method kept at u is converged.
  const bool reached = satisfied(sys, x, newton, it, norm);
  satisfied_now = reached;
  if (reached && same_set) out_.status = SolveStatus::kConverged;
  // A method whose solve costs more than a Newton iteration or two (ipopt's interior
  // point, a penalty raised or augmented many times) is not asked again for a step
  // Newton with the set held can finish: it is asked only to confirm.
  const bool cheap = s0.factorizations <= kCheapStrategy;
  if (reached || (cheap && std::isfinite(norm) && norm <= step_decrease_ * last_norm_)) {
    it.newton = NewtonReport{};  // the method's step as one Newton iteration
    it.newton.status = SolveStatus::kConverged;
    it.newton.iterations = 1;
    it.newton.final_residual = norm;
    it.newton.residual_norms = {norm};
    it.newton.last_step = inf_norm(s.u);
    add_newton(it);
  } else if (!newton_with_set_held(sys, x, newton, it, true, !continued_,
                                   cheap ? step_decrease_ * last_norm_ : 0.0)) {
    return false;
  } else {
    satisfied_now = it.newton.status == SolveStatus::kConverged &&
                    it.newton.final_residual <= tolerance(sys, newton);
  }
  return true;
}

bool ConstrainedStep::settled(const ConstrainedProblem& qp, double tolerance) const {
  const bool friction = qp.has_friction();
  const ConstraintStrategy::StateTest test = method().state_test(qp);
  if (!test.rule || system_.is_linear() || !(state_.max_penetration <= test.max_penetration))
    return false;
  const int slots = contact_.num_slots();
  std::vector<char> held(slots, 0), found(slots, 0);
  std::vector<int> row_of(slots, -1);
  for (size_t i = 0; i < rows_.size(); ++i) row_of[rows_[i].slot] = static_cast<int>(i);
  for (size_t i = 0; i < rows_.size() && i < state_.active.size(); ++i)
    held[rows_[i].slot] = state_.active[i] != 0;
  double scale = 0.0;
  for (const double f : force_by_slot_) scale = std::max(scale, std::abs(f));
  const RuleScales scales = rule_scales(qp, scale, saddle_point_scale(qp));
  const SetRule& rule = *test.rule;
  const int m = qp.num_gaps();
  const bool tangential_state = state_.tangent_force.size() == m && state_.slip.size() == m &&
                                state_.friction_state.size() == static_cast<size_t>(m);
  for (const GapRow& r : contact_.detect(system_.full(u_), false, false)) {
    found[r.slot] = 1;
    RowSolution row;
    row.held = held[r.slot] != 0;
    row.force = row.held ? force_by_slot_[r.slot] : 0.0;
    row.gap = r.gap;
    // A regularised rule judging a state reads no estimate (λ̂ = 0, the pure penalty's): −k g,
    // whose sign any k > 0 gives.
    if (rule.regularised()) row.penalty = 1.0, row.force_estimate = 0.0;
    const NormalDecision d = rule.normal(row, scales);
    if (d.held != row.held) return false;
    const int i = row_of[r.slot];
    if (!friction || i < 0 || !qp.frictional(i)) continue;
    // Friction (exact methods): the state's sticking rows within their bound, its slipping
    // rows still slipping the way their force points, at the bound of the state's normal
    // force (Newton held their forces at the solve's), as the rule decides from the state.
    if (qp.friction_binds_open(i) || !tangential_state) return false;  // Tresca: the method's
    if (!row.held) continue;
    row.tangent_force = state_.tangent_force[i];
    row.slip = state_.slip[i];
    const bool stick = state_.friction_state[i] == FrictionState::kStick;
    row.tangential = stick ? kStick : row.tangent_force > 0 ? kSlipPlus : kSlipMinus;
    double residual = 0.0;
    const double bound = qp.friction_limit(i, d.normal), at_state = qp.friction_limit(i, row.force);
    if (rule.tangential(row, d, bound, scales, residual) != row.tangential) return false;
    if (!stick && std::abs(std::abs(row.tangent_force) - at_state) > tolerance) return false;
  }
  for (int k = 0; k < slots; ++k)
    if (held[k] && !found[k]) return false;
  return true;
}

bool ConstrainedStep::satisfied(ActiveSetSystem& sys, const VecX& x, const NewtonOptions& newton,
                                ContactIteration& it, double& norm) const {
  VecX r;
  norm = sys.residual(x, r) ? inf_norm(r) : std::numeric_limits<double>::infinity();
  if (!(norm <= tolerance(sys, newton))) return false;
  it.newton.status = SolveStatus::kConverged;
  it.newton.final_residual = inf_norm(r);
  it.newton.residual_norms = {it.newton.final_residual};
  return true;
}

double ConstrainedStep::tolerance(const ActiveSetSystem& sys, const NewtonOptions& newton) const {
  return std::max(newton.residual_tolerance * newton.residual_scale, round_off_floor(sys));
}

void ConstrainedStep::add_newton(ContactIteration& it) {
  out_.newton.iterations += it.newton.iterations;
  out_.newton.method_steps += it.newton.method_steps;
  out_.newton.factorizations += it.newton.factorizations;
  it.factorizations += it.newton.factorizations;
  out_.newton.residual_norms.insert(out_.newton.residual_norms.end(),
                                    it.newton.residual_norms.begin(),
                                    it.newton.residual_norms.end());
  out_.newton.final_residual = it.newton.final_residual;
  out_.newton.last_step = it.newton.last_step;
}

double ConstrainedStep::round_off_floor(const ActiveSetSystem& sys) const {
  return 16.0 * std::numeric_limits<double>::epsilon() * coordinate_scale_ * sys.row_stiffness();
}

bool ConstrainedStep::newton_with_set_held(ActiveSetSystem& sys, VecX& x,
                                           const NewtonOptions& options, ContactIteration& it,
                                           bool from_method_step, bool may_continue,
                                           double enough) {
  // KINSOL's test is relative to the scale: never below what the rows' round-off allows (a
  // stiff penalty on an obstacle row otherwise leaves Newton stuck a decade above its test,
  // ending on a zero step).
  NewtonOptions newton = options;
  if (newton.residual_scale > 0)
    newton.residual_tolerance =
        std::max({newton.residual_tolerance, round_off_floor(sys) / newton.residual_scale,
                  std::isfinite(enough) ? enough / newton.residual_scale : 0.0});
  it.newton = solve_newton_with_fallback(sys, x, newton);
  if (from_method_step) {  // x is the method's step: Newton's first iteration
    ++it.newton.iterations;
    ++it.newton.method_steps;
  }
  add_newton(it);
  if (it.newton.status == SolveStatus::kConverged) return true;
  // A solve that ran out of iterations or stalled after halving the residual at least hands
  // its state to the next outer iteration, once an attempt: the set it held may be the one
  // that stopped fitting (a node sliding past its master's free end cannot keep g = 0), and
  // the method decides the set anew there. The step still ends only on a state that
  // satisfies the equations with a set the method keeps.
  const auto& norms = it.newton.residual_norms;
  if (may_continue &&
      (it.newton.status == SolveStatus::kMaxIterations ||
       it.newton.status == SolveStatus::kStalled) &&
      !norms.empty() && std::isfinite(it.newton.final_residual) &&
      it.newton.final_residual < 0.5 * norms.front()) {
    continued_ = true;
    return true;
  }
  out_.iterations.push_back(it);
  fail(it.newton.status, where_ + "Newton with the active set fixed: " + it.newton.message);
  return false;
}

void ConstrainedStep::keep_state(ActiveSetSystem& sys, const VecX& x, const ConstraintSolution& s,
                                 ContactIteration& it, const std::vector<int>& stick) {
  state_ = s;
  state_.u = u_;
  VecX held_gap;
  sys.gap(x, held_gap);  // evaluated by the solve's last residual
  const VecX held_force = sys.forces(x, held_gap);
  const int ms = static_cast<int>(stick.size());
  const int m = sys.num_gaps(), me = static_cast<int>(held_gap.size()) - m - ms;
  state_rows_ = sys.rows();
  state_.gap = held_gap.head(m);
  state_.contact_force = held_force.head(m);
  state_.eq_residual = held_gap.segment(m, me);
  state_.eq_multiplier = held_force.segment(m, me);
  for (int k = 0; k < ms; ++k) {  // the sticking rows' friction forces and slips after Newton
    state_.tangent_force[stick[k]] = held_force[m + me + k];
    state_.slip[stick[k]] = -held_gap[m + me + k];
  }
  state_.max_eq_violation = inf_norm(state_.eq_residual);
  state_.max_penetration = max_penetration(state_.gap);
  std::fill(force_by_slot_.begin(), force_by_slot_.end(), 0.0);
  for (size_t i = 0; i < rows_.size(); ++i)
    force_by_slot_[rows_[i].slot] = state_.contact_force[static_cast<int>(i)];
  if (state_.tangent_force.size() == m) {
    tangent_by_slot_ = VecX::Zero(contact_.num_slots());
    for (int i = 0; i < m; ++i) tangent_by_slot_[rows_[i].slot] = state_.tangent_force[i];
  }
  it.max_penetration = state_.max_penetration;
  it.max_force = inf_norm(state_.contact_force);
  ContactReport report;
  contact_.report(state_rows_, state_, report);
  it.max_pressure = report.p_max;
}

}  // namespace c2d::nonlinear
