#include "nonlinear/contact_newton.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

#include "constraints/strategy_common.hpp"
#include "core/stopwatch.hpp"
#include "nonlinear/constrained_step.hpp"
#include "nonlinear/first_touch.hpp"

namespace c2d::nonlinear {

using namespace c2d::constraints;

ConstrainedStep::ConstrainedStep(StructuralSystem& system, const ContactSet& contact,
                                 ConstraintStrategy& strategy, const ContactStepInput& in)
    : system_(system),
      contact_(contact),
      strategy_(strategy),
      in_(in),
      u_(in.u_free),
      previous_(strategy.history().states),
      force_by_slot_(contact.num_slots(), 0.0),
      slip_origin_(contact.num_slots()),
      step_decrease_(in.strict || !strategy.exact() ? kStrictStepDecrease : kStepDecrease) {
  previous_.resize(contact.num_slots(), 0);
  // The step's starting set belongs to the last converged state, not to this step: a set
  // that returns to it (the predictor closed a row that the corrected state opens again) is
  // no cycle. A cycle is a set that returns among this step's own outer iterations.
  sets_.follow(previous_);
  // Small strain: the rows' gaps come from absolute coordinates. Finite strain: from positions
  // relative to a node of the row, with the displacement kept apart (gap_linearisation.hpp),
  // so their round-off is that of the local lengths and of the displacements themselves: an
  // iterate's u is known to ε|u| at best (a block dragged by 3 carries 7e-16 in each value,
  // which a penalty of 5e6 turns into a force of 4e-9 that no Newton step can remove).
  // A rigid obstacle's rows (the slave node its only term) take their gaps from absolute
  // coordinates whatever the kinematics.
  for (const Vec2& xn : system.model().mesh.nodes)
    absolute_scale_ = std::max(absolute_scale_, xn.cwiseAbs().maxCoeff());
  displacement_scale_ = inf_norm(in.u_free);
  absolute_scale_ += displacement_scale_ + contact.model_size();
  coordinate_scale_ =
      system.is_linear() ? absolute_scale_ : contact.length_scale() + displacement_scale_;
}

ContactStepResult ConstrainedStep::run() {
  for (int outer = 1; outer <= in_.max_outer; ++outer) {
    where_ = "outer iteration " + std::to_string(outer) + ": ";
    if (!iterate(outer)) return std::move(out_);
    if (out_.status == SolveStatus::kConverged) break;
  }
  if (out_.status == SolveStatus::kConverged) {
    out_.newton.status = SolveStatus::kConverged;
    out_.history = {previous_, tangent_by_slot_,
                    Eigen::Map<const VecX>(force_by_slot_.data(),
                                           static_cast<int>(force_by_slot_.size())),
                    closing_reach_};
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

bool ConstrainedStep::iterate(int outer) {
  ContactIteration it;
  it.outer = outer;
  // 1. The problem linearised at the current state. The first iteration starts from the
  //    stepper's extrapolated start when it has one (linearised there as any later iterate),
  //    else from the previous step's converged state with the prescribed increment as a lift.
  const bool guess = outer == 1 && in_.u_guess.size() == u_.size() &&
                     system_.admissible(system_.full(in_.u_guess));
  if (guess) u_ = in_.u_guess;
  if (outer == 1) from_guess_ = guess;
  const VecX u_full = system_.full(u_);
  VecX load;
  if (outer == 1 && !guess ? !system_.step_predictor(in_.u_prev_full, load)
                           : !linearise(u_full, load)) {
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
            : contact_.length_scale() + displacement_scale_;
  out_.detection_seconds += detection.lap();
  // A linear system whose state reproduces the rows and gaps it was solved with poses the
  // same problem again: the strategy would return the same set and no step.
  if (outer > 1 && system_.is_linear() && reproduces_state()) {
    out_.status = SolveStatus::kConverged;
    return true;
  }
  ConstrainedProblem qp = contact_.problem(tangent(outer, u_full), load, rows_, u_full,
                                           system_.is_linear(), &in_.u_prev_full);
  memory_ = {};  // what the method carries into this problem, filled below
  VecX c(qp.num_gaps() + qp.num_equalities());  // g(u_f) = c + G u_f, then A u_f − b
  c << qp.gap0, -qp.eq_rhs;
  qp.gap0 += qp.gap_jacobian * u_;  // the gaps and equalities in terms of the step Δu
  qp.eq_rhs -= qp.eq_jacobian * u_;
  if (qp.slip0.size() == qp.num_gaps()) {  // friction: the slip since the last step
    qp.slip0 += qp.slip_jacobian * u_;
    slip_origin_.apply(rows_, strategy_.history(), previous_, tangent_by_slot_, qp, memory_);
  }
  keep_local_stiffness(qp);
  warm_start(qp, rows_, previous_, force_by_slot_, memory_);
  // A step's first iterate may close rows as far as the last step's did, and a little more.
  if (outer == 1) memory_.closing_reach = kReachMargin * strategy_.history().closing_reach;

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
  if (change.repeated && hand_to_fallback("its sets cycled")) {
    if (!solve_method(qp, c, it, s, next)) return false;
    change = sets_.record(next);
  }
  const bool same_set = change.unchanged;
  if (change.repeated) {
    out_.iterations.push_back(it);
    fail(SolveStatus::kCycling,
         where_ + "the active set returned to an earlier set within the step");
    return false;
  }
  // 3. Newton with the set fixed.
  if (!hold_set(qp, c, s, same_set, it)) return false;
  previous_ = next;
  return true;
}

bool ConstrainedStep::solve_method(const ConstrainedProblem& qp, const VecX& c,
                                   ContactIteration& it, ConstraintSolution& s,
                                   ContactMemory& next) {
  s = solve_catching_first_touch(method(), qp, memory_);
  out_.strategy.add(s);
  // A problem the method cannot pose goes to its fallback, for this iterate and the rest of
  // the step, as a cycle does.
  if (s.status != SolveStatus::kConverged && !s.not_applicable.empty() &&
      hand_to_fallback(s.not_applicable)) {
    it.factorizations += s.factorizations;
    s = solve_catching_first_touch(method(), qp, memory_);
    out_.strategy.add(s);
  }
  if (s.status == SolveStatus::kConverged && static_cast<int>(s.active.size()) == qp.num_gaps() &&
      static_cast<int>(memory_.initial_active.size()) == qp.num_gaps())
    for (int i = 0; i < qp.num_gaps(); ++i)
      if (s.active[i] && !memory_.initial_active[i])
        closing_reach_ = std::max(closing_reach_, qp.gap0[i]);
  it.factorizations += s.factorizations;
  next = record_strategy(qp, s, it);
  if (s.status == SolveStatus::kConverged) return true;
  keep_partial(c, qp, s);
  out_.iterations.push_back(it);
  fail(s.status, where_ + method().name() + ": " + s.message);
  return false;
}

bool ConstrainedStep::hand_to_fallback(const std::string& reason) {
  if (fallback_ || !(fallback_ = strategy_.fallback())) return false;
  out_.fallback = fallback_->name();
  out_.fallback_reason = reason;
  return true;
}

SpMat ConstrainedStep::tangent(int outer, const VecX& u_full) const {
  SpMat k = system_.matrix();
  if (system_.is_linear()) return k;
  // The first iterate from the extrapolated start: the rows' curvature under the forces the
  // last converged state held (the method's history), the best estimate of the forces there,
  // so that its step is a Newton step too (the frictional drag: 4.8 factorisations a step with
  // penalty without it, 4.2 with it). Not from the tangent predictor, whose first iterate is a
  // step across the whole increment: there the term joins the bodies' blocks of the surface
  // factor for nothing (Cattaneo–Mindlin: the same iterations, 20 % more triangular work).
  const VecX& start = strategy_.history().normal_force;
  VecX f(static_cast<int>(rows_.size()));
  for (size_t i = 0; i < rows_.size(); ++i) {
    const int slot = rows_[i].slot;
    f[static_cast<int>(i)] =
        std::max(0.0, outer > 1 ? force_by_slot_[slot]
                                : (from_guess_ && slot < start.size() ? start[slot] : 0.0));
  }
  if (f.size() > 0 && f.maxCoeff() > 0.0) k += contact_.geometric_stiffness(rows_, f);
  if (outer == 1) return k;
  if (contact_.has_nonlinear_equalities() && state_.eq_multiplier.size() > 0) {
    const std::vector<EqualityRow> eq = contact_.equality_rows_at(u_full, false);
    if (static_cast<int>(eq.size()) == state_.eq_multiplier.size())
      k += contact_.equality_geometric_stiffness(eq, state_.eq_multiplier);
  }
  return k;
}

bool ConstrainedStep::linearise(const VecX& u_full, VecX& load) {
  VecX r;
  if (!system_.residual(u_, r) || !system_.assemble_tangent(u_full)) return false;
  load = -r;
  return true;
}

bool ConstrainedStep::reproduces_state() const {
  const int m = static_cast<int>(rows_.size());
  if (rows_.size() != state_rows_.size() || state_.gap.size() != m ||
      static_cast<int>(state_.active.size()) != m)
    return false;
  const double tol = 1e-9 * contact_.model_size();
  for (int i = 0; i < m; ++i) {
    if (rows_[i].slave != state_rows_[i].slave) return false;
    const bool consistent =
        state_.active[i] ? std::abs(rows_[i].gap - state_.gap[i]) <= tol : rows_[i].gap >= -tol;
    if (!consistent) return false;
  }
  return true;
}

void ConstrainedStep::keep_local_stiffness(const ConstrainedProblem& qp) {
  memory_.gap_row_stiffness = qp.surface_stiffness();
  local_by_slot_.resize(contact_.num_slots(), 0.0);
  for (int i = 0; i < qp.num_gaps(); ++i) {
    double& kept = local_by_slot_[rows_[i].slot];
    if (kept > 0.0)
      memory_.gap_row_stiffness[i] = kept;
    else
      kept = memory_.gap_row_stiffness[i];
  }
}

ContactMemory ConstrainedStep::record_strategy(const ConstrainedProblem& qp,
                                               const ConstraintSolution& s,
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
                            : s.tangent_force[i] >= 0                                ? 2
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

void ConstrainedStep::keep_partial(const VecX& c, const ConstrainedProblem& qp,
                                   const ConstraintSolution& s) {
  if (s.u.size() != u_.size()) return;
  out_.u_free = u_ + s.u;
  out_.rows = rows_;
  out_.state = s;
  out_.state.u = out_.u_free;
  out_.state.gap = c.head(qp.num_gaps()) + qp.gap_jacobian * out_.u_free;
}

void ConstrainedStep::verify_final_state() {
  const std::vector<GapRow> fresh = contact_.detect(system_.full(u_), system_.is_linear(), false);
  double measured = 0.0;
  for (const GapRow& r : fresh) measured = std::max(measured, -r.gap);
  out_.measured_penetration = measured;
  out_.nodal_penetration = contact_.nodal_penetration(system_.full(u_));
  // The state may penetrate where it holds a row (a regularised method's force over its
  // stiffness); a row it leaves open, by the method's penetration tolerance at most.
  double held = 0.0;
  const int m = static_cast<int>(std::min<size_t>(state_.gap.size(), state_.active.size()));
  for (int i = 0; i < m; ++i)
    if (state_.active[i]) held = std::max(held, -state_.gap[i]);
  const double open = penetration_tolerance(contact_.options(), contact_.length_scale());
  out_.penetration_tolerance =
      std::min(state_.max_penetration, std::max(held, open)) + 1e-9 * contact_.model_size();
  if (out_.status == SolveStatus::kConverged && measured > out_.penetration_tolerance)
    fail(SolveStatus::kPenetration, "the final state penetrates by " + number_text(measured) +
                                        ", beyond the " + number_text(out_.penetration_tolerance) +
                                        " the method allows");
  // An exact method's state may not leave a slave node below the deformed master surface
  // beyond the physical limit, whatever its rows say (mortar's weighted gaps, a linear
  // analysis's linearised ones): measured on the final geometry, independently of them. A
  // regularised method converges to its own penetration; the report warns of it.
  const double limit = contact_.penetration_limit();
  if (out_.status == SolveStatus::kConverged && method().exact() && out_.nodal_penetration > limit)
    fail(SolveStatus::kPenetration,
         "a slave node lies " + number_text(out_.nodal_penetration) +
             " below the deformed master surface, beyond the physical limit " + number_text(limit) +
             " (penetration_limit x the shortest contact edge), although "
             "the method's rows hold");
}

void ConstrainedStep::fail(SolveStatus status, const std::string& message) {
  out_.status = status;
  out_.message = message;
}

void StrategyTotals::add(const ConstraintSolution& s) {
  const int offset = history.empty() ? 0 : history.back().iteration;
  for (IterationRecord rec : s.history) {
    rec.iteration += offset;
    history.push_back(rec);
  }
  penalty_history.insert(penalty_history.end(), s.penalty_history.begin(), s.penalty_history.end());
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
