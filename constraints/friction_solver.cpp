#include "constraints/friction_solver.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "constraints/frictional_solve.hpp"
#include "core/interrupt.hpp"

namespace c2d::constraints {

VecX tangent_penalties(const ConstrainedProblem& p, const VecX& k_gap) {
  VecX k_t = k_gap;
  if (p.tangent_penalty_ratio.size() == k_gap.size())
    k_t = k_gap.cwiseProduct(p.tangent_penalty_ratio);
  return k_t;
}

namespace {

/// The rows of a sparse matrix as (column, value) lists.
std::vector<std::vector<std::pair<int, double>>> row_lists(const SpMat& a, double sign) {
  std::vector<std::vector<std::pair<int, double>>> rows(a.rows());
  for (int c = 0; c < a.outerSize(); ++c)
    for (SpMat::InnerIterator it(a, c); it; ++it)
      if (it.value() != 0.0) rows[it.row()].emplace_back(c, sign * it.value());
  return rows;
}

}  // namespace

FrictionalSolve::FrictionalSolve(const ConstrainedProblem& p, const RowMemory& memory)
    : p_(p),
      memory_(memory),
      n_(p.num_unknowns()),
      me_(p.num_equalities()),
      m_(p.num_gaps()),
      s_(saddle_point_scale(p)),
      eq_rows_(row_lists(p.eq_jacobian, 1.0)),
      gap_rows_(row_lists(p.gap_jacobian, 1.0)),
      slip_rows_(row_lists(p.slip_jacobian, -1.0)),
      slip0_(p.slip0.size() == m_ ? p.slip0 : VecX::Zero(m_)) {
  // A frictionless problem has no tangential rows: each row's is empty, its slip zero, and
  // its tangential force zero (the row is free along the surface).
  slip_rows_.resize(m_);
  pieces_.resize(m_);
  binds_open_.assign(m_, 0);
  for (int i = 0; i < m_; ++i) binds_open_[i] = p.friction_binds_open(i);
}

void FrictionalSolve::run(const FrictionalOptions& options, ConstraintSolution& s) {
  o_ = &options;
  rule_ = o_->rule ? o_->rule : &primal_dual_;
  penalised_ = rule_->regularised();
  const KktSolveReport before = kkt_.report();
  counted_ = surface_report();
  dense_counted_ = surface_ ? surface_->dense_seconds() : 0.0;
  const std::vector<char> cold = cold_start();
  std::vector<char> code = warm_start(cold);
  bool warm = code != cold;
  ActiveSetTracker sets;
  sets.record(code);
  s.status = SolveStatus::kMaxIterations;
  s.message = "stick, slip and contact sets still changing after " +
              std::to_string(o_->max_iterations) + " iterations";
  bool solved = false;
  int it = 0;
  StallMonitor stall;
  for (int k = 0; k < o_->max_iterations; ++k) {
    it = o_->first_iteration + k;
    core::check_interrupt();
    if (const SolveStatus st = solve(code, s); st != SolveStatus::kConverged) {
      solve_failed(st, code, s);
      break;
    }
    solved = true;
    VecX g = p_.gap0 + p_.gap_jacobian * s.u;
    const VecX sl = slip(s.u);
    // (a row left out of the condensation has no value on the tail: its gap is read on the
    // whole displacement once the sets settle)
    for (int i = 0; i < m_; ++i)
      if (surface_last_ && !in_play(i)) g[i] = std::max(p_.gap0[i], 0.0);
    // A penalised row held on the condensed surface: its gap from its force, g = (λ̂ − w)/k,
    // as its row of the block states it. From u, a stiff penalty's gap (1000 N / 1e20 N/mm)
    // sits at the round-off of the tail's displacements, and its sign is noise.
    if (penalised_ && surface_last_)
      for (int i = 0; i < m_; ++i)
        if (code[i]) g[i] = (o_->lambda_hat[i] - s.contact_force[i]) / o_->k_gap[i];
    std::vector<char> next = code;
    const double residual = update(s, g, sl, next);
    s.history.push_back(record(it, code, next, g, residual));
    const ActiveSetTracker::Change change = sets.record(next);
    if (change.unchanged && surface_last_ && bring_into_play(s, next)) {
      drop_surface(s);  // (made again with them)
      sets.restart(next);
      code = next;
      continue;
    }
    if (change.unchanged) {
      s.status = SolveStatus::kConverged;
      s.message.clear();
      break;
    }
    if (change.repeated) {
      if (const SetRule* fallback = rule_->on_cycle()) {
        // A rule without globalisation (the semi-smooth step) hands a cycle to its fallback.
        rule_ = fallback;
        sets.restart(next);
      } else if (warm) {
        // A warm start is a guess: one that leads into a cycle is dropped for the cold one.
        warm = false;
        next = cold;
        sets.restart(next);
      } else {
        s.status = SolveStatus::kCycling;
        s.message = "stick, slip and contact sets returned to an earlier combination at "
                    "iteration " + std::to_string(it);
        break;
      }
    }
    if (safeguarded() && !stall.progress(change)) {
      s.message = "contact set not settling after " + std::to_string(it) + " iterations";
      break;
    }
    code = next;
  }
  if (solved && safeguarded() &&
      (s.status == SolveStatus::kCycling || s.status == SolveStatus::kMaxIterations))
    safeguard(it, code, s);
  if (solved && surface_last_) complete_displacement(s);
  // Summed: a method may call repeatedly (stiffness raises, multiplier updates).
  add_solver_work(kkt_.report(), before, s);
  count_surface_work(s);
  s.pivot_ratio = surface_last_ ? surface_rcond_ : kkt_.report().rcond;
  // The factorisation the solution came from, named in the solver section.
  if (surface_last_)
    s.factor = surface_report();
  else if (kkt_.report().numeric_factorizations > 0)
    s.factor = kkt_.report();
  finish(code, solved, s);
}

void FrictionalSolve::solve_failed(SolveStatus st, const std::vector<char>& code,
                                   ConstraintSolution& s) const {
  s.status = st;
  s.message = failure_message();
  bool sticks = false, slips = false;
  for (int i = 0; i < m_; ++i)
    if (code[i] && frictional(i))
      sticks = sticks || code[m_ + i] == kStick, slips = slips || code[m_ + i] >= kSlipPlus;
  if (st == SolveStatus::kSingular && slips && !sticks)
    s.message += "; every closed frictional row slips, so nothing holds the bodies along "
                 "the surface: friction cannot carry the load";
}

std::vector<char> FrictionalSolve::normal_code(const std::vector<char>& set) const {
  std::vector<char> code(3 * m_, kFree);
  std::copy(set.begin(), set.end(), code.begin());
  return code;
}

void FrictionalSolve::safeguard(int it, std::vector<char>& code, ConstraintSolution& s) {
  const SetSolve solve_set = [&](const std::vector<char>& set, ConstraintSolution& out,
                                 std::string& why) {
    const SolveStatus st = solve(normal_code(set), out);
    if (st != SolveStatus::kConverged) why = failure_message();
    return st;
  };
  const std::string before = s.message;
  for (;;) {
    VecX shift = VecX::Zero(m_);  // (a penalised row enters where λ̂ − k g > 0)
    for (int i = 0; i < m_; ++i)
      shift[i] = !in_play(i) ? -std::numeric_limits<double>::infinity()
                 : penalised_ ? o_->lambda_hat[i] / o_->k_gap[i]
                              : 0.0;
    std::vector<char> active(code.begin(), code.begin() + m_);
    std::string why;
    const SolveStatus st = dual_active_set(p_, solve_set, shift, o_->max_iterations + 2 * m_,
                                           it, active, s, why);
    code = normal_code(active);
    ConstraintSolution whole;
    if (solve(code, whole) == SolveStatus::kConverged) {
      s.u = whole.u;
      s.eq_multiplier = whole.eq_multiplier;
      s.contact_force = whole.contact_force;
      s.tangent_force = whole.tangent_force;
    }
    s.message = st == SolveStatus::kConverged ? "" : before + "; " + why;
    s.status = st;
    if (st != SolveStatus::kConverged || !surface_last_ || !bring_into_play(s, code)) return;
    drop_surface(s);
    it = s.history.empty() ? it : s.history.back().iteration;
  }
}

std::vector<char> FrictionalSolve::cold_start() const {
  std::vector<char> cold(3 * m_, kFree);
  const std::vector<char> closed = initially_closed(p_, memory_);
  const bool forces = memory_.initial_force.size() == m_;
  for (int i = 0; i < m_; ++i) {
    cold[i] = closed[i] && (penalised_ || !gap_rows_[i].empty());
    if (frictional(i) && (cold[i] || tresca(i))) cold[m_ + i] = kStick;
    if (frictional(i)) cold[2 * m_ + i] = piece_code(i, forces ? memory_.initial_force[i] : 0.0);
  }
  return cold;
}

char FrictionalSolve::piece_code(int i, double normal) const {
  const FrictionBound b = p_.friction_bound(i, normal);
  std::vector<FrictionBound>& known = pieces_[i];
  if (std::none_of(known.begin(), known.end(), [&](const FrictionBound& k) { return k.piece == b.piece; }))
    known.push_back(b);
  return static_cast<char>(b.piece);
}

const FrictionBound& FrictionalSolve::piece_of(int i, char piece) const {
  for (const FrictionBound& b : pieces_[i])
    if (b.piece == piece) return b;
  return pieces_[i].front();  // (unreachable: every code comes from piece_code)
}

std::vector<char> FrictionalSolve::warm_start(const std::vector<char>& cold) const {
  std::vector<char> code = cold;
  for (int i = 0; i < m_; ++i)
    if (code[m_ + i] == kStick && static_cast<int>(memory_.initial_friction.size()) == m_ &&
        memory_.initial_friction[i] >= 1 && memory_.initial_friction[i] <= 3)
      code[m_ + i] = memory_.initial_friction[i];  // the same codes
  const ConstraintSolution* st = o_->start;
  if (!st || static_cast<int>(st->active.size()) != m_ ||
      static_cast<int>(st->friction_state.size()) != m_ || st->tangent_force.size() != m_)
    return code;
  for (int i = 0; i < m_; ++i) {
    code[i] = st->active[i] && (penalised_ || !gap_rows_[i].empty());
    code[m_ + i] = kFree;
    if (!frictional(i)) continue;
    code[2 * m_ + i] = piece_code(i, st->contact_force.size() == m_ ? st->contact_force[i] : 0.0);
    if (!code[i] && !tresca(i)) continue;
    // (an open Tresca row carries friction: it slips when its force reached the bound)
    const double open_bound = p_.friction_limit(i, 0.0);
    const bool slips = st->friction_state[i] == FrictionState::kSlip ||
                       (!code[i] && std::abs(st->tangent_force[i]) >= (1 - 1e-6) * open_bound);
    code[m_ + i] = slips ? (st->tangent_force[i] >= 0 ? kSlipPlus : kSlipMinus) : kStick;
  }
  return code;
}

VecX FrictionalSolve::slip(const VecX& u) const {
  return p_.slip_jacobian.rows() == m_ && p_.slip_jacobian.cols() == n_
             ? VecX(slip0_ + p_.slip_jacobian * u)
             : slip0_;
}

double FrictionalSolve::update(const ConstraintSolution& sol, const VecX& g, const VecX& sl,
              std::vector<char>& next) const {
  const VecX& lambda = sol.contact_force;
  const VecX& lt = sol.tangent_force;
  double scale = 0.0;
  for (int i = 0; i < m_; ++i) scale = std::max({scale, std::abs(lambda[i]), std::abs(lt[i])});
  const RuleScales scales = rule_scales(p_, scale, s_);
  double residual = 0.0;
  for (int i = 0; i < m_; ++i) {
    if (!in_play(i)) {
      next[i] = 0;
      next[m_ + i] = kFree;
      continue;
    }
    RowSolution r;
    r.force = lambda[i];
    r.gap = g[i];
    r.tangent_force = lt[i];
    r.slip = sl[i];
    r.held = next[i] != 0;
    r.tangential = next[m_ + i];
    r.closable = !gap_rows_[i].empty();
    if (penalised_) {
      r.penalty = o_->k_gap[i], r.tangent_penalty = o_->k_tangent[i];
      r.force_estimate = o_->lambda_hat[i], r.tangent_estimate = o_->tangent_hat[i];
    }
    const NormalDecision d = rule_->normal(r, scales);
    residual = std::max(residual, d.residual);
    next[i] = d.held;
    if (!frictional(i) || (!d.held && !tresca(i))) {
      next[m_ + i] = kFree;
      continue;
    }
    // A row that enters takes the piece at zero normal force, the one it closes on (an open
    // row's trial force measures its penetration, not its force: starting a capped law's row
    // on its cap from it made the sets cycle); a held row the piece at its force.
    next[2 * m_ + i] = piece_code(i, r.held ? d.normal : 0.0);
    r.entry_slip_allowance = tresca(i) ? scales.gap_tolerance
                                       : p_.friction_bound(i, 0.0).slope * std::abs(g[i]);
    const double bound = p_.friction_limit(i, d.normal);
    next[m_ + i] = rule_->tangential(r, d, bound, scales, residual);
  }
  return residual;
}

IterationRecord FrictionalSolve::record(int it, const std::vector<char>& code, const std::vector<char>& next,
                       const VecX& g, double residual) const {
  IterationRecord rec;
  rec.iteration = it;
  for (int i = 0; i < m_; ++i) {
    rec.active += next[i];
    rec.entering += next[i] && !code[i];
    rec.leaving += !next[i] && code[i];
    rec.stick += next[i] && next[m_ + i] == kStick;
    rec.slip += next[i] && (next[m_ + i] == kSlipPlus || next[m_ + i] == kSlipMinus ||
                            !frictional(i));
  }
  rec.max_penetration = max_penetration(g);
  rec.residual = residual;
  return rec;
}

void FrictionalSolve::finish(const std::vector<char>& code, bool solved, ConstraintSolution& s) const {
  if (!solved) {
    s.u = VecX::Zero(n_);
    s.contact_force = VecX::Zero(m_);
    s.tangent_force = VecX::Zero(m_);
    s.eq_multiplier = VecX::Zero(me_);
  }
  s.contact_force = s.contact_force.cwiseMax(0.0);
  s.active.assign(m_, 0);
  s.friction_state.assign(m_, FrictionState::kOpen);
  for (int i = 0; i < m_; ++i) {
    s.active[i] = penalised_ ? s.contact_force[i] > 0 : code[i] != 0;
    if (!s.active[i]) continue;  // (a Tresca row may carry friction while open)
    // A frictionless row slides freely.
    s.friction_state[i] =
        frictional(i) && code[m_ + i] == kStick ? FrictionState::kStick : FrictionState::kSlip;
  }
}

FrictionalSolver::FrictionalSolver(const ConstrainedProblem& p, const RowMemory& memory)
    : impl_(std::make_unique<FrictionalSolve>(p, memory)) {}
FrictionalSolver::~FrictionalSolver() = default;

void FrictionalSolver::solve(const FrictionalOptions& options, ConstraintSolution& s) {
  impl_->run(options, s);
}

bool FrictionalSolver::share(const std::shared_ptr<SurfaceCondensation>& surface) {
  return impl_->share(surface);
}

bool confirm_exactly(FrictionalSolver& solver, int max_solves, ConstraintSolution& s,
                     std::string& why) {
  const PrimalDualRule rule;
  FrictionalOptions o;
  o.rule = &rule;
  o.max_iterations = max_solves;
  o.safeguard = false;
  o.start = &s;
  ConstraintSolution exact;
  solver.solve(o, exact);
  add_solution_work(exact, s);
  if (exact.status != SolveStatus::kConverged) {
    why = exact.message;
    return false;
  }
  for (IterationRecord r : exact.history) {
    r.iteration = (s.history.empty() ? 0 : s.history.back().iteration) + 1;
    s.history.push_back(r);
  }
  s.u = exact.u;
  s.contact_force = exact.contact_force;
  s.tangent_force = exact.tangent_force;
  s.eq_multiplier = exact.eq_multiplier;
  s.friction_state = exact.friction_state;
  s.active = exact.active;
  return true;
}

void solve_frictional(const ConstrainedProblem& p, const RowMemory& memory,
                      const FrictionalOptions& options, ConstraintSolution& s) {
  FrictionalSolver(p, memory).solve(options, s);
}

ConstraintSolution solve_frictional(const ConstrainedProblem& p, const RowMemory& memory,
                                    const SetRule& rule, int max_iterations) {
  FrictionalOptions o;
  o.rule = &rule;
  o.max_iterations = max_iterations;
  ConstraintSolution s;
  solve_frictional(p, memory, o, s);
  return s;
}

}  // namespace c2d::constraints
