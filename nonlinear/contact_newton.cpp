#include "nonlinear/contact_newton.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

#include "constraints/active_set_tracker.hpp"
#include "constraints/strategy_common.hpp"
#include "core/stopwatch.hpp"
#include "nonlinear/active_set_system.hpp"
#include "nonlinear/first_touch.hpp"
#include "nonlinear/held_friction.hpp"
#include "nonlinear/slip_origin.hpp"


namespace c2d::nonlinear {

using namespace c2d::constraints;

namespace {

double inf_norm(const VecX& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

/// A strategy step is kept as the next iterate when it divides the residual by ten at least
/// (Newton's quadratic rate near a solution); a slower one is finished by Newton with the set
/// held, whose rows follow the iterate (a node sliding onto the next master edge).
constexpr double kStepDecrease = 0.1;
/// Factorisations a strategy's solve may cost for its step to be kept that way.
constexpr int kCheapStrategy = 2;

}  // namespace

namespace {

/// One load step's outer iterations (see contact_newton.hpp), as named steps over the state
/// they share: the current free displacements, the active set by slot, the last solve's row
/// forces, and the last state that satisfied the equations with its set held.
class ConstrainedStep {
 public:
  ConstrainedStep(StructuralSystem& system, const ContactSet& contact,
                  ConstraintStrategy& strategy, const ContactStepInput& in)
      : system_(system), contact_(contact), strategy_(strategy), in_(in), u_(in.u_free),
        previous_(strategy.history().states), force_by_slot_(contact.num_slots(), 0.0),
        slip_origin_(contact.num_slots()) {
    previous_.resize(contact.num_slots(), 0);
    // The step's starting set belongs to the last converged state, not to this step: a set
    // that returns to it (the predictor closed a row that the corrected state opens again) is
    // no cycle. A cycle is a set that returns among this step's own outer iterations.
    sets_.follow(previous_);
    // Small strain: the rows' gaps come from absolute coordinates. Finite strain: from positions
    // relative to a node of the row, with the displacement kept apart (gap_linearisation.hpp),
    // so their round-off is that of the local lengths.
    // A rigid obstacle's rows (the slave node its only term) take their gaps from absolute
    // coordinates whatever the kinematics.
    for (const Vec2& xn : system.model().mesh.nodes)
      absolute_scale_ = std::max(absolute_scale_, xn.cwiseAbs().maxCoeff());
    absolute_scale_ += inf_norm(in.u_free) + contact.model_size();
    coordinate_scale_ = system.is_linear() ? absolute_scale_ : contact.length_scale();
  }

  ContactStepResult run() {
    for (int outer = 1; outer <= in_.max_outer; ++outer) {
      where_ = "outer iteration " + std::to_string(outer) + ": ";
      if (!iterate(outer)) return std::move(out_);
      if (out_.status == SolveStatus::kConverged) break;
    }
    if (out_.status == SolveStatus::kConverged) {
      out_.newton.status = SolveStatus::kConverged;
      out_.history = {previous_, tangent_by_slot_};
      verify_final_state();
    } else {
      fail(SolveStatus::kMaxIterations, "active set or geometry still changing after " +
                                            std::to_string(in_.max_outer) + " outer iterations");
      verify_final_state();
    }
    // The last state that satisfied the equations with its set held: the rows and forces of
    // the solve that produced it (converged: the strategy confirmed their linearisation there).
    out_.u_free = u_;
    out_.rows = std::move(state_rows_);
    out_.state = std::move(state_);
    return std::move(out_);
  }

 private:
  /// One outer iteration; false when the step failed (out_ says why), out_.status converged
  /// when it ended the step.
  bool iterate(int outer) {
    ContactIteration it;
    it.outer = outer;
    // 1. The problem linearised at the current state. The first iteration starts from the
    //    previous step's converged state and carries the prescribed increment as a lift.
    const VecX u_full = system_.full(u_);
    VecX load;
    if (outer == 1 ? !system_.step_predictor(in_.u_prev_full, load) : !linearise(u_full, load)) {
      const std::string which = system_.evaluation_failure();
      fail(SolveStatus::kInvertedElement,
           where_ + (which.empty() ? std::string("an element is inverted") : which));
      return false;
    }
    core::Stopwatch detection;
    rows_ = contact_.detect(u_full, system_.is_linear());
    if (!system_.is_linear())
      coordinate_scale_ =
          std::any_of(rows_.begin(), rows_.end(), [](const GapRow& r) { return r.terms.size() == 1; })
              ? absolute_scale_
              : contact_.length_scale();
    out_.detection_seconds += detection.lap();
    // A linear system whose state reproduces the rows and gaps it was solved with poses the
    // same problem again: the strategy would return the same set and no step.
    if (outer > 1 && system_.is_linear() && reproduces_state()) {
      out_.status = SolveStatus::kConverged;
      return true;
    }
    ConstrainedProblem qp = contact_.problem(tangent(outer, u_full), load, rows_, u_full,
                                             system_.is_linear(), &in_.u_prev_full);
    VecX c(qp.num_gaps() + qp.num_equalities());  // g(u_f) = c + G u_f, then A u_f − b
    c << qp.gap0, -qp.eq_rhs;
    qp.gap0 += qp.gap_jacobian * u_;     // the gaps and equalities in terms of the step Δu
    qp.eq_rhs -= qp.eq_jacobian * u_;
    if (qp.slip0.size() == qp.num_gaps()) {  // friction: the slip since the last step
      qp.slip0 += qp.slip_jacobian * u_;
      slip_origin_.apply(rows_, strategy_.history(), previous_, tangent_by_slot_, qp);
    }
    keep_local_stiffness(qp);
    warm_start(qp, rows_, previous_, force_by_slot_);

    // 2. The strategy on the linearised problem.
    ConstraintSolution s;
    ContactMemory next;
    if (!solve_method(qp, c, it, s, next)) return false;
    // The first iteration's set is the predictor's, at the step's start: it may come back.
    ActiveSetTracker::Change change;
    if (outer == 1)
      sets_.follow(next);
    else
      change = sets_.record(next);
    // Sets that cycle end the step, unless the method has a fallback to finish it with: then
    // this iterate is solved again by the fallback, and so is every later one of the step.
    if (change.repeated && !fallback_ && (fallback_ = strategy_.cycle_fallback())) {
      out_.fallback = fallback_->name();
      if (!solve_method(qp, c, it, s, next)) return false;
      change = sets_.record(next);
    }
    const bool same_set = change.unchanged;
    if (change.repeated) {
      out_.iterations.push_back(it);
      fail(SolveStatus::kCycling, where_ + "the active set returned to an earlier set within the step");
      return false;
    }
    // 3. Newton with the set fixed.
    if (!hold_set(qp, c, s, same_set, it)) return false;
    previous_ = next;
    return true;
  }

  /// The method solving the step's iterates: the step's own, or its cycle fallback.
  ConstraintStrategy& method() const { return fallback_ ? *fallback_ : strategy_; }

  /// The method's solve of the linearised problem `qp` (constants `c`), its work and set in
  /// the iteration record `it`; `next` its active set by slot. False when it failed: its trial
  /// state kept, the step failed with its status.
  bool solve_method(ConstrainedProblem& qp, const VecX& c, ContactIteration& it,
                    ConstraintSolution& s, ContactMemory& next) {
    s = solve_catching_first_touch(method(), qp);
    out_.strategy.add(s);
    it.factorizations += s.factorizations;
    next = record_strategy(qp, s, it);
    if (s.status == SolveStatus::kConverged) return true;
    keep_partial(c, qp, s);
    out_.iterations.push_back(it);
    fail(s.status, where_ + method().name() + ": " + s.message);
    return false;
  }

  /// The stiffness the strategy linearises with: K_T, and from the second outer iteration on
  /// the rows' curvature under the state's forces (the contact's and the plates' geometric
  /// stiffness, as Newton's Jacobian has it), so that the strategy's step is a Newton step.
  SpMat tangent(int outer, const VecX& u_full) const {
    SpMat k = system_.matrix();
    if (outer == 1 || system_.is_linear()) return k;
    VecX f(static_cast<int>(rows_.size()));
    for (size_t i = 0; i < rows_.size(); ++i)
      f[static_cast<int>(i)] = std::max(0.0, force_by_slot_[rows_[i].slot]);
    k += contact_.geometric_stiffness(rows_, f);
    if (contact_.has_nonlinear_equalities() && state_.eq_multiplier.size() > 0) {
      const std::vector<EqualityRow> eq = contact_.equality_rows_at(u_full, false);
      if (static_cast<int>(eq.size()) == state_.eq_multiplier.size())
        k += contact_.equality_geometric_stiffness(eq, state_.eq_multiplier);
    }
    return k;
  }

  /// The out-of-balance force and tangent at u_full (outer iterations after the first).
  bool linearise(const VecX& u_full, VecX& load) {
    VecX r;
    if (!system_.residual(u_, r) || !system_.assemble_tangent(u_full)) return false;
    load = -r;
    return true;
  }

  /// The rows detected now are those of the kept state (same slave nodes); the closed ones have
  /// the gaps its linearisation predicted (a node sliding along a flat master changes edge, not
  /// gap) and the open ones do not penetrate. An open row's gap need not match its
  /// linearisation (a node passing a free master end turns its normal): it carries no force.
  bool reproduces_state() const {
    const int m = static_cast<int>(rows_.size());
    if (rows_.size() != state_rows_.size() || state_.gap.size() != m ||
        static_cast<int>(state_.active.size()) != m)
      return false;
    const double tol = 1e-9 * contact_.model_size();
    for (int i = 0; i < m; ++i) {
      if (rows_[i].slave != state_rows_[i].slave) return false;
      const bool consistent = state_.active[i] ? std::abs(rows_[i].gap - state_.gap[i]) <= tol
                                               : rows_[i].gap >= -tol;
      if (!consistent) return false;
    }
    return true;
  }

  /// The rows' local stiffness (the base of default penalties) as the step first met each slot.
  void keep_local_stiffness(ConstrainedProblem& qp) {
    qp.gap_row_stiffness = qp.surface_stiffness();
    local_by_slot_.resize(contact_.num_slots(), 0.0);
    for (int i = 0; i < qp.num_gaps(); ++i) {
      double& kept = local_by_slot_[rows_[i].slot];
      if (kept > 0.0)
        qp.gap_row_stiffness[i] = kept;
      else
        kept = qp.gap_row_stiffness[i];
    }
  }

  /// The strategy's figures in the iteration record; returns its active set by slot.
  ContactMemory record_strategy(const ConstrainedProblem& qp, const ConstraintSolution& s,
                                ContactIteration& it) const {
    const int m = qp.num_gaps(), slots = contact_.num_slots();
    it.strategy_iterations = s.iterations;
    it.strategy_status = s.status;
    it.strategy_step = inf_norm(s.u);
    it.rows = m;
    ContactMemory next(slots, 0);
    const bool friction = static_cast<int>(s.friction_state.size()) == m;
    for (int i = 0; i < m; ++i)
      if (s.active[i])
        next[rows_[i].slot] = !friction || s.friction_state[i] != FrictionState::kSlip ? 1
                              : s.tangent_force[i] >= 0                           ? 2
                                                                                  : 3;
    for (int k = 0; k < slots; ++k) {
      it.entering += next[k] && !previous_[k];
      it.leaving += !next[k] && previous_[k];
      it.active += next[k] != 0;
      if (friction) it.stick += next[k] == 1, it.slip += next[k] >= 2;
    }
    it.penalty = s.penalty.size() ? s.penalty.maxCoeff() : 0.0;
    return next;
  }

  /// A strategy that stopped short (iteration limit, cycle, ill-conditioning) leaves its
  /// trial state for a caller that reports it as such.
  void keep_partial(const VecX& c, const ConstrainedProblem& qp, const ConstraintSolution& s) {
    if (s.u.size() != u_.size()) return;
    out_.u_free = u_ + s.u;
    out_.rows = rows_;
    out_.state = s;
    out_.state.u = out_.u_free;
    out_.state.gap = c.head(qp.num_gaps()) + qp.gap_jacobian * out_.u_free;
  }

  /// KINSOL with the set fixed, from the strategy's step when the set changed, from the state
  /// itself (and its own multipliers) when the strategy kept it; no solve when the start
  /// already satisfies the equations. False when Newton failed.
  bool hold_set(const ConstrainedProblem& qp0, const VecX& c0, const ConstraintSolution& s0,
                bool same_set, ContactIteration& it) {
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
    newton.residual_scale = std::max({newton.residual_scale, inf_norm(s.contact_force),
                                      inf_norm(s.eq_multiplier),
                                      system_.reaction_scale(x.head(u_.size())), in_.floor_scale,
                                      step_scale_});
    step_scale_ = newton.residual_scale;
    // The step: the strategy's solve of the problem linearised at u is a Newton step with the
    // sets updated. The step ends where the method kept its set at u and the state already
    // satisfies the equations with that set held, or its step reached such a state. A step
    // that does not divide the residual by ten is finished by Newton with the set held
    // (KINSOL, line search), the globalisation.
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
    } else {
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
                     ? inf_norm(r) : std::numeric_limits<double>::quiet_NaN();
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
      if (reached || (cheap && std::isfinite(norm) && norm <= kStepDecrease * last_norm_)) {
        it.newton = NewtonReport{};  // the method's step as one Newton iteration
        it.newton.status = SolveStatus::kConverged;
        it.newton.iterations = 1;
        it.newton.final_residual = norm;
        it.newton.residual_norms = {norm};
        it.newton.last_step = inf_norm(s.u);
        add_newton(it);
      } else if (!newton_with_set_held(sys, x, newton, it, true, !continued_,
                                       cheap ? kStepDecrease * last_norm_ : 0.0)) {
        return false;
      } else {
        satisfied_now = it.newton.status == SolveStatus::kConverged &&
                        it.newton.final_residual <= tolerance(sys, newton);
      }
    }
    last_norm_ = it.newton.final_residual;
    u_ = x.head(u_.size());
    keep_state(sys, x, s0, it, friction ? friction->stick : std::vector<int>());
    // A state that satisfies the equations with its set held, where the method's rule keeps
    // that set, ends the step: asking the method again would factorise only to confirm.
    if (satisfied_now && out_.status != SolveStatus::kConverged && settled(qp0))
      out_.status = SolveStatus::kConverged;
    out_.iterations.push_back(it);
    return true;
  }

  /// Whether the method's rule keeps, at the state just kept, the set it was solved with: the
  /// rows detected afresh there, each held slot still a row that the rule holds (compressive),
  /// every other row one it leaves open (not penetrating). Frictionless methods whose set
  /// follows from the state (ConstraintStrategy::set_follows_state): friction's states follow
  /// from slips the next linearisation measures.
  bool settled(const ConstrainedProblem& qp) const {
    if (!method().set_follows_state() || qp.has_friction() || system_.is_linear()) return false;
    const int slots = contact_.num_slots();
    std::vector<char> held(slots, 0), found(slots, 0);
    for (size_t i = 0; i < rows_.size() && i < state_.active.size(); ++i)
      held[rows_[i].slot] = state_.active[i] != 0;
    double scale = 0.0;
    for (const double f : force_by_slot_) scale = std::max(scale, std::abs(f));
    const RuleScales scales = rule_scales(qp, scale, saddle_point_scale(qp));
    for (const GapRow& r : contact_.detect(system_.full(u_), false, false)) {
      found[r.slot] = 1;
      RowSolution row;
      row.held = held[r.slot] != 0;
      row.force = row.held ? force_by_slot_[r.slot] : 0.0;
      row.gap = r.gap;
      // A regularised method whose set follows the state has no estimate (λ̂ = 0): its rule
      // reads −k g, whose sign any k > 0 gives.
      if (!method().exact()) row.penalty = 1.0, row.force_estimate = 0.0;
      if (method().set_rule().normal(row, scales).held != row.held) return false;
    }
    for (int k = 0; k < slots; ++k)
      if (held[k] && !found[k]) return false;
    return true;
  }

  /// Whether x already satisfies the equations. A gap detected from absolute coordinates
  /// carries their round-off, ε·|x|, which a row stiffness k turns into a force of k·ε·|x|:
  /// with penalties 1e3 times the element stiffness that floor can exceed the tolerance, so it
  /// bounds the test from below.
  bool satisfied(ActiveSetSystem& sys, const VecX& x, const NewtonOptions& newton,
                 ContactIteration& it, double& norm) const {
    VecX r;
    norm = sys.residual(x, r) ? inf_norm(r) : std::numeric_limits<double>::infinity();
    if (!(norm <= tolerance(sys, newton))) return false;
    it.newton.status = SolveStatus::kConverged;
    it.newton.final_residual = inf_norm(r);
    it.newton.residual_norms = {it.newton.final_residual};
    return true;
  }

  /// The residual a state must reach to satisfy the equations with the set held: the Newton
  /// test, never below the residual's round-off floor.
  double tolerance(const ActiveSetSystem& sys, const NewtonOptions& newton) const {
    return std::max(newton.residual_tolerance * newton.residual_scale, round_off_floor(sys));
  }

  /// An iterate's Newton work (its factorisations, iterations, norms) into the step's.
  void add_newton(ContactIteration& it) {
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

  /// The residual's round-off floor with the set held: a gap's round-off, ε·|x|, times the
  /// stiffest row.
  double round_off_floor(const ActiveSetSystem& sys) const {
    return 16.0 * std::numeric_limits<double>::epsilon() * coordinate_scale_ * sys.row_stiffness();
  }

  /// KINSOL with the set held from x; false when it failed (out_ says why). With
  /// `from_method_step`, x is the method's step, counted as that Newton's first iteration.
  /// With `may_continue`, true also where it handed an unconverged state on (see below:
  /// it.newton.status says so). Newton stops at a residual of `enough` when that is above the
  /// test: the set it holds was decided at a state far from this one, and the method decides
  /// it again once Newton is back in its quadratic range (the state's residual divided by
  /// ten), rather than after Newton has converged with a set that may be about to change.
  bool newton_with_set_held(ActiveSetSystem& sys, VecX& x, const NewtonOptions& options,
                            ContactIteration& it, bool from_method_step,
                            bool may_continue = false, double enough = 0.0) {
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

  /// The held state: `stick` lists the sticking rows held after the equality rows.
  void keep_state(ActiveSetSystem& sys, const VecX& x, const ConstraintSolution& s,
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

  /// "converged" is checked on the final state: the rows detected afresh at the final
  /// positions (paired there; a linear run's gaps linearised as its analysis is) may not
  /// penetrate beyond what the method reports. Each slave node's depth below the deformed
  /// master surface, in the final geometry, is measured beside it. A failed step is measured too.
  void verify_final_state() {
    const std::vector<GapRow> fresh =
        contact_.detect(system_.full(u_), system_.is_linear(), false);
    double measured = 0.0;
    for (const GapRow& r : fresh) measured = std::max(measured, -r.gap);
    out_.measured_penetration = measured;
    out_.nodal_penetration = contact_.nodal_penetration(system_.full(u_));
    out_.penetration_tolerance = state_.max_penetration + 1e-9 * contact_.model_size();
    if (out_.status == SolveStatus::kConverged && measured > out_.penetration_tolerance)
      fail(SolveStatus::kPenetration,
           "the final state penetrates by " + number_text(measured) + ", beyond the " +
               number_text(state_.max_penetration) + " the method reports");
  }

  void fail(SolveStatus status, const std::string& message) {
    out_.status = status;
    out_.message = message;
  }

  StructuralSystem& system_;
  const ContactSet& contact_;
  ConstraintStrategy& strategy_;
  std::unique_ptr<ConstraintStrategy> fallback_;  ///< the cycle fallback, once called on
  const ContactStepInput& in_;
  VecX u_;
  ContactMemory previous_;
  ActiveSetTracker sets_;  ///< the sets by slot of the outer iterations (cycle detection)
  std::vector<double> force_by_slot_;  ///< the last solve's row forces
  VecX tangent_by_slot_;               ///< friction: the held state's friction forces
  SlipOrigin slip_origin_;  ///< friction: where each row's slip starts in the step
  std::vector<double> local_by_slot_;  ///< each slot's local stiffness, as first met (0: not yet)
  double step_scale_ = 0.0;            ///< the largest residual scale of the step so far
  bool continued_ = false;  ///< a held solve that did not converge handed its state on
  /// The residual a method's step must divide by ten to be kept as a Newton step: the larger
  /// of the last state's and the state's residual with what the step holds (∞ before the first).
  double last_norm_ = std::numeric_limits<double>::infinity();
  double coordinate_scale_ = 0.0;      ///< the lengths a gap is computed from, for round-off
  double absolute_scale_ = 0.0;        ///< the coordinates' size (gaps from absolute positions)
  std::vector<GapRow> rows_, state_rows_;
  ConstraintSolution state_;
  std::string where_;
  ContactStepResult out_;
};

}  // namespace

void StrategyTotals::add(const ConstraintSolution& s) {
  const int offset = history.empty() ? 0 : history.back().iteration;
  for (IterationRecord rec : s.history) {
    rec.iteration += offset;
    history.push_back(rec);
  }
  penalty_history.insert(penalty_history.end(), s.penalty_history.begin(),
                         s.penalty_history.end());
  iterations += s.iterations;
  seconds += s.seconds;
  factorizations += s.factorizations;
  symbolic_analyses += s.symbolic_analyses;
  symbolic_seconds += s.symbolic_seconds;
  numeric_seconds += s.numeric_seconds;
  solve_seconds += s.solve_seconds;
  pivot_ratio = s.pivot_ratio;
  if (!s.factor.ordering.empty()) factor = s.factor;
}

void StrategyTotals::add_work(const StrategyTotals& t) {
  iterations += t.iterations;
  factorizations += t.factorizations;
  symbolic_analyses += t.symbolic_analyses;
  seconds += t.seconds;
  symbolic_seconds += t.symbolic_seconds;
  numeric_seconds += t.numeric_seconds;
  solve_seconds += t.solve_seconds;
  if (std::isfinite(t.pivot_ratio)) pivot_ratio = t.pivot_ratio;
  if (!t.factor.ordering.empty()) factor = t.factor;
}

double residual_floor_scale(const core::Model& model) {
  // A nodal force computed from strains carries a round-off of a few ε·E·t·h whatever the
  // stress (the strain of F = I + ∇u is exact to ε only), largest at the largest elements: on
  // a block moved rigidly off its master (no load, no reaction) Newton's residual floor was
  // 1.8e-12 = 45 ε·E·t·h_min, above the test 1e-8 × 1e-6 E·t·h_min, and the step never
  // converged. 1e-5 E·t·h_max × the tolerance 1e-8 is ~450 ε·E·t·h_max.
  double e_t = 0.0;
  for (const auto& m : model.materials) e_t = std::max(e_t, m.young * m.thickness);
  return 1e-5 * e_t * model.mesh.edge_length_range().second;
}

ContactStepResult solve_contact_step(StructuralSystem& system, const ContactSet& contact,
                                     ConstraintStrategy& strategy, const ContactStepInput& in) {
  return ConstrainedStep(system, contact, strategy, in).run();
}

}  // namespace c2d::nonlinear
