#include "constraints/friction_solver.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "constraints/kkt_solver.hpp"
#include "constraints/set_rules.hpp"
#include "constraints/strategy_common.hpp"
#include "constraints/surface_condensation.hpp"
#include "core/interrupt.hpp"

namespace c2d::constraints {

VecX tangent_penalties(const ConstrainedProblem& p, const VecX& k_gap) {
  VecX k_t = k_gap;
  if (p.tangent_penalty_ratio.size() == k_gap.size())
    k_t = k_gap.cwiseProduct(p.tangent_penalty_ratio);
  return k_t;
}

namespace {

// The sets, as the iteration tracks them: entry i (a gap row) is 1 when the row is held, entry
// m + i its tangential row's state (set_rules.hpp's Tangential), entry 2m + i the piece of its
// friction law that bounds it. A Coulomb row's tangential row is free while its normal row is;
// a Tresca row's (a law whose bound is positive at zero normal force) is not tied to it (the
// classical Tresca problem bounds the friction on the whole candidate surface, which keeps it
// convex: tying it to contact made the bound switch on and off with the contact and the sets
// cycle).

/// The rows of a sparse matrix as (column, value) lists.
std::vector<std::vector<std::pair<int, double>>> row_lists(const SpMat& a, double sign) {
  std::vector<std::vector<std::pair<int, double>>> rows(a.rows());
  for (int c = 0; c < a.outerSize(); ++c)
    for (SpMat::InnerIterator it(a, c); it; ++it)
      if (it.value() != 0.0) rows[it.row()].emplace_back(c, sign * it.value());
  return rows;
}

}  // namespace

class FrictionalSolve {
 public:
  FrictionalSolve(const ConstrainedProblem& p, const RowMemory& memory)
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

  void run(const FrictionalOptions& options, ConstraintSolution& s) {
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
        s.status = st;
        s.message = message_.empty() ? kkt_.report().message : message_;
        bool sticks = false, slips = false;
        for (int i = 0; i < m_; ++i)
          if (code[i] && frictional(i))
            sticks = sticks || code[m_ + i] == kStick, slips = slips || code[m_ + i] >= kSlipPlus;
        if (st == SolveStatus::kSingular && slips && !sticks)
          s.message += "; every closed frictional row slips, so nothing holds the bodies along "
                       "the surface: friction cannot carry the load";
        break;
      }
      solved = true;
      VecX g = p_.gap0 + p_.gap_jacobian * s.u;
      const VecX sl = slip(s.u);
      // (a row left out of the condensation has no value on the tail: its gap is read on the
      // whole displacement once the sets settle)
      for (int i = 0; i < m_; ++i)
        if (surface_last_ && !in_play(i)) g[i] = std::max(p_.gap0[i], 0.0);
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

 private:
  /// Whether a set iteration that cycles or wanders is finished by the dual active-set
  /// safeguard: a frictionless problem with an exact rule (the safeguard's steps keep λ ≥ 0
  /// and raise the dual objective, which a friction law's slip conditions do not fit).
  bool safeguarded() const { return o_->safeguard && !penalised_ && !p_.has_friction(); }

  /// The sets of a frictionless problem: the gap rows of `set` held, every tangential row free.
  std::vector<char> normal_code(const std::vector<char>& set) const {
    std::vector<char> code(3 * m_, kFree);
    std::copy(set.begin(), set.end(), code.begin());
    return code;
  }

  /// The dual active-set method (strategy_common.hpp) from the sets `code`, each set solved on
  /// the same factor, among the rows in play (the others cannot enter: their gaps are not on
  /// the tail); then the last set solved on its own, so that the state is that set's solution,
  /// and the left-out rows checked on the whole displacement: where one closes, they come into
  /// play and the safeguard runs again on the condensation made with them. `s` gets the
  /// status, the history and the state; `code` the last set.
  void safeguard(int it, std::vector<char>& code, ConstraintSolution& s) {
    const SetSolve solve_set = [&](const std::vector<char>& set, ConstraintSolution& out,
                                   std::string& why) {
      const SolveStatus st = solve(normal_code(set), out);
      if (st != SolveStatus::kConverged) why = message_.empty() ? kkt_.report().message : message_;
      return st;
    };
    const std::string before = s.message;
    for (;;) {
      VecX shift = VecX::Zero(m_);
      for (int i = 0; i < m_; ++i)
        if (!in_play(i)) shift[i] = -std::numeric_limits<double>::infinity();
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

  /// The memory's closed rows, every frictional one (and every Tresca row) sticking, each on
  /// its law's piece at the warm start's normal force (or none).
  std::vector<char> cold_start() const {
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

  /// The code of row i's law piece at normal force `normal` (and the piece remembered).
  char piece_code(int i, double normal) const {
    const FrictionBound b = p_.friction_bound(i, normal);
    std::vector<FrictionBound>& known = pieces_[i];
    if (std::none_of(known.begin(), known.end(), [&](const FrictionBound& k) { return k.piece == b.piece; }))
      known.push_back(b);
    return static_cast<char>(b.piece);
  }

  /// Row i's law piece of code `piece` (one piece_code() returned).
  const FrictionBound& piece_of(int i, char piece) const {
    for (const FrictionBound& b : pieces_[i])
      if (b.piece == piece) return b;
    return pieces_[i].front();  // (unreachable: every code comes from piece_code)
  }

  /// The cold start with the previous state's friction states, or a given solution's sets.
  std::vector<char> warm_start(const std::vector<char>& cold) const {
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

  bool frictional(int i) const { return p_.frictional(i); }
  /// The rows' slip at u (zero without tangential rows).
  VecX slip(const VecX& u) const {
    return p_.slip_jacobian.rows() == m_ && p_.slip_jacobian.cols() == n_
               ? VecX(slip0_ + p_.slip_jacobian * u)
               : slip0_;
  }
  bool tresca(int i) const { return binds_open_[i] != 0; }
  double compliance(const VecX& k, int i) const { return penalised_ ? 1.0 / k[i] : 0.0; }

  /// Solves the system of the sets `code` into s.u, λ, λ_t, μ: condensed onto the rows when
  /// K (regularised) factorises, else (or when the rows' dense block is singular) by LU of the
  /// whole saddle point. On the condensed path s.u holds the tail's values only (all the rules
  /// read) until complete_displacement().
  SolveStatus solve(const std::vector<char>& code, ConstraintSolution& out) {
    SolveStatus condensed = SolveStatus::kFailed;
    if (surface_ready(code)) {
      condensed = solve_condensed(code, out);
      if (condensed == SolveStatus::kConverged) {
        surface_last_ = true;
        return SolveStatus::kConverged;
      }
      surface_message_ = surface_->message();
      // The whole saddle point has every row in play, and so has a condensation made again.
      if (!all_in_play()) drop_surface(out);
    }
    surface_last_ = false;
    play_.assign(m_, 1);
    const SolveStatus st = solve_lu(code, out);
    // A set whose condensed block is singular and whose LU solve keeps no precision is
    // singular: the block says why (a free body, dependent rows).
    if (st == SolveStatus::kIllConditioned && condensed == SolveStatus::kSingular) {
      message_ = surface_message_;
      return SolveStatus::kSingular;
    }
    message_.clear();
    return st;
  }

  SolveStatus solve_lu(const std::vector<char>& code, ConstraintSolution& out) {
    const int size = n_ + me_ + 2 * m_;
    const double s = s_;
    std::vector<Triplet> t;
    t.reserve(p_.stiffness.nonZeros() + 4 * (p_.eq_jacobian.nonZeros() +
                                             p_.gap_jacobian.nonZeros() +
                                             p_.slip_jacobian.nonZeros()) + 3 * (me_ + 2 * m_));
    for (int c = 0; c < p_.stiffness.outerSize(); ++c)
      for (SpMat::InnerIterator it(p_.stiffness, c); it; ++it) t.emplace_back(it.row(), c, it.value());
    VecX rhs = VecX::Zero(size);
    rhs.head(n_) = p_.load;
    // One row: its coefficients in both blocks (the row's own only when it holds c = 0).
    auto add_row = [&](int r, const std::vector<std::pair<int, double>>& coef, bool holds) {
      for (const auto& [j, a] : coef) {
        t.emplace_back(j, r, -s * a);
        t.emplace_back(r, j, holds ? -s * a : 0.0);
      }
    };
    for (int j = 0; j < me_; ++j) {
      const int r = n_ + j;
      add_row(r, eq_rows_[j], true);
      const double cmp = compliance(o_->k_eq, j);
      t.emplace_back(r, r, -s * s * cmp);
      rhs[r] = -s * p_.eq_rhs[j] - (penalised_ ? s * cmp * o_->mu_hat[j] : 0.0);
    }
    for (int i = 0; i < m_; ++i) {
      const int rn = n_ + me_ + i, rt = n_ + me_ + m_ + i;
      const bool on = code[i];
      add_row(rn, gap_rows_[i], on);
      const double cn = compliance(o_->k_gap, i);
      t.emplace_back(rn, rn, on ? -s * s * cn : s);
      rhs[rn] = on ? s * p_.gap0[i] - (penalised_ ? s * cn * o_->lambda_hat[i] : 0.0) : 0.0;
      // The tangential row: held when sticking (with a tangential row to hold), a slip
      // condition when slipping, λ_t = 0 otherwise.
      const char ts = code[m_ + i];
      const bool stick = ts == kStick && (penalised_ || !slip_rows_[i].empty());
      const bool slip = ts == kSlipPlus || ts == kSlipMinus;
      const double sigma = ts == kSlipMinus ? -1.0 : 1.0;
      add_row(rt, slip_rows_[i], stick);
      const double ct = compliance(o_->k_tangent, i);
      t.emplace_back(rt, rt, stick ? -s * s * ct : s);
      // slipping: λ_t = σ (offset + slope λ) on the row's piece of its law
      const FrictionBound b = frictional(i) ? piece_of(i, code[2 * m_ + i]) : FrictionBound{};
      t.emplace_back(rt, rn, slip ? -s * b.slope * sigma : 0.0);
      if (stick)
        rhs[rt] = -s * slip0_[i] - (penalised_ ? s * ct * o_->tangent_hat[i] : 0.0);
      else if (slip)
        rhs[rt] = sigma * b.offset;
    }
    // The matrix depends on the sets and the stiffnesses only: an augmented Lagrangian's next
    // multiplier update with the same sets needs a new right-hand side, not a new factor.
    const bool same = factored_ && code == factored_code_ && (!penalised_ ||
                      (o_->k_gap == factored_k_[0] && o_->k_tangent == factored_k_[1] &&
                       o_->k_eq == factored_k_[2]));
    SolveStatus st = SolveStatus::kConverged;
    if (!same) {
      SpMat a(size, size);
      a.setFromTriplets(t.begin(), t.end());
      st = kkt_.factorize(a, analysed_);
      analysed_ = true;
      factored_ = st == SolveStatus::kConverged;
      factored_code_ = code;
      if (penalised_) factored_k_ = {o_->k_gap, o_->k_tangent, o_->k_eq};
    }
    VecX x;
    if (st == SolveStatus::kConverged) st = kkt_.solve(rhs, x);
    if (st != SolveStatus::kConverged) return st;
    out.u = x.head(n_);
    out.eq_multiplier = s * x.segment(n_, me_);
    out.contact_force = s * x.segment(n_ + me_, m_);
    out.tangent_force = s * x.segment(n_ + me_ + m_, m_);
    return st;
  }

  core::SpdSolveReport surface_report() const {
    return surface_ ? surface_->report() : core::SpdSolveReport{};
  }

  /// The condensation of K onto the rows in play (equality, normal, tangential: row r = j,
  /// me + i, me + m + i), factorised on first use with R = the equality rows and the eight
  /// normal rows nearest to closing with their tangential rows, or every row when those leave
  /// a rigid mode. In play: every equality row, the gap rows the sets `code` hold or that are
  /// closed at the linearisation point, every Tresca row (bound while open), and a margin of
  /// the open rows nearest to closing (choose_play()); the others are free and stay out of the
  /// tail, whose dense factor costs the cube of its size (a contact zone of 155 rows among 253
  /// candidates: half the flops). bring_into_play() checks them on the whole displacement.
  bool surface_ready(const std::vector<char>& code) {
    if (surface_tried_) return surface_ != nullptr;
    surface_tried_ = true;
    if (play_.empty()) choose_play(code);
    SpMat ct = surface_rows();
    std::vector<int> eq(me_);
    for (int j = 0; j < me_; ++j) eq[j] = j;
    std::vector<std::vector<int>> groups(m_);
    for (int i = 0; i < m_; ++i) groups[i] = {me_ + i, me_ + m_ + i};
    surface_ = condense_onto_rows(std::move(ct), p_.stiffness, p_.ordering, eq,
                                  std::move(groups),
                                  std::vector<double>(p_.gap0.begin(), p_.gap0.end()));
    first_row_ = 0;
    return surface_ != nullptr;
  }

 public:
  /// Takes `surface`, a condensation of this problem's K, for the condensed path, with this
  /// solver's rows appended to it; false (and nothing changed) when they cannot be, or when
  /// this solver already chose its path.
  bool share(const std::shared_ptr<SurfaceCondensation>& surface) {
    if (surface_tried_ || !surface) return false;
    const int first = surface->add_rows(surface_rows());
    if (first < 0) return false;
    surface_ = surface;
    first_row_ = first;
    surface_tried_ = true;
    play_.assign(m_, 1);
    return true;
  }

 private:
  /// Cᵀ over this solver's rows: equality j, normal me + i, tangential me + m + i.
  SpMat surface_rows() const {
    std::vector<Triplet> t;
    auto put = [&](int r, const std::vector<std::pair<int, double>>& coef) {
      for (const auto& [j, a] : coef) t.emplace_back(j, r, a);
    };
    for (int j = 0; j < me_; ++j) put(j, eq_rows_[j]);
    for (int i = 0; i < m_; ++i)
      if (in_play(i)) put(me_ + i, gap_rows_[i]), put(me_ + m_ + i, slip_rows_[i]);
    SpMat ct(n_, me_ + 2 * m_);
    ct.setFromTriplets(t.begin(), t.end());
    return ct;
  }

  /// The sets' system on the rows, in forces w = s z: a held row's saddle-point equation
  /// −s c·u − s² cmp z = rhs is c·u + cmp w = −rhs/s; a slipping row's force follows its normal
  /// row's, w_t = σ(offset + slope w_n); a free row's is zero.
  SolveStatus solve_condensed(const std::vector<char>& code, ConstraintSolution& out) {
    SurfaceCondensation::RowStates st;
    const int eq = first_row_, normal = first_row_ + me_, tangential = normal + m_;
    for (int j = 0; j < me_; ++j) {
      const double c = compliance(o_->k_eq, j);
      st.hold(eq + j, c, p_.eq_rhs[j] + (penalised_ ? c * o_->mu_hat[j] : 0.0));
    }
    for (int i = 0; i < m_; ++i) {
      if (code[i]) {
        const double c = compliance(o_->k_gap, i);
        st.hold(normal + i, c, -p_.gap0[i] + (penalised_ ? c * o_->lambda_hat[i] : 0.0));
      }
      const char ts = code[m_ + i];
      if (ts == kStick && (penalised_ || !slip_rows_[i].empty())) {
        const double c = compliance(o_->k_tangent, i);
        st.hold(tangential + i, c, slip0_[i] + (penalised_ ? c * o_->tangent_hat[i] : 0.0));
      } else if (ts == kSlipPlus || ts == kSlipMinus) {
        const double sigma = ts == kSlipMinus ? -1.0 : 1.0;
        const FrictionBound b = frictional(i) ? piece_of(i, code[2 * m_ + i]) : FrictionBound{};
        st.follow(tangential + i, code[i] ? normal + i : -1, sigma * b.offset, sigma * b.slope);
      }
    }
    VecX w;
    const SolveStatus status = surface_->solve(p_.load, st, w, out.u, surface_rcond_);
    if (status != SolveStatus::kConverged) return status;
    out.eq_multiplier = w.segment(eq, me_);
    out.contact_force = w.segment(normal, m_);
    out.tangent_force = w.segment(tangential, m_);
    return status;
  }

  /// The whole u of the last condensed solve (the rules needed its tail only).
  void complete_displacement(ConstraintSolution& s) {
    VecX u;
    if (surface_->complete(u) == SolveStatus::kConverged) s.u = u;
  }

  bool in_play(int i) const { return play_.empty() || play_[i]; }
  bool all_in_play() const {
    return std::all_of(play_.begin(), play_.end(), [](char c) { return c != 0; });
  }

  /// The condensation's work since it was last counted, added to `s`.
  void count_surface_work(ConstraintSolution& s) {
    add_solver_work(surface_report(), counted_, s);
    const double dense = surface_ ? surface_->dense_seconds() : 0.0;
    s.solve_seconds += dense - dense_counted_;
    counted_ = surface_report();
    dense_counted_ = dense;
  }

  /// Counts the condensation's work and drops it: the next solve makes it again (with the
  /// rows in play then).
  void drop_surface(ConstraintSolution& s) {
    count_surface_work(s);
    surface_.reset();
    surface_tried_ = false;
    counted_ = {};
    dense_counted_ = 0.0;
  }

  /// The rows in play (see surface_ready()): those `code` holds, the closed and the Tresca rows,
  /// those within the memory's closing reach (how far the last load step's contact grew), and
  /// a margin of the open rows nearest to closing (an eighth as many as those, at least 8). Every row when that would leave out fewer than a quarter of them or 48 (a dense tail
  /// that small costs less than the second factorisation a row that closes outside would take),
  /// or when fewer than an eighth of them or 8 are closed: a contact that is only beginning
  /// grows out of any margin (on Cattaneo–Mindlin, from 1 row to 79), and a body it alone
  /// holds is singular on its first rows.
  void choose_play(const std::vector<char>& code) {
    play_.assign(m_, 0);
    std::vector<int> open;
    int count = 0;
    for (int i = 0; i < m_; ++i) {
      play_[i] = code[i] || tresca(i) || p_.gap0[i] <= std::max(0.0, memory_.closing_reach);
      play_[i] ? void(++count) : open.push_back(i);
    }
    const int margin = std::min<int>(open.size(), std::max(8, count / 8));
    std::partial_sort(open.begin(), open.begin() + margin, open.end(),
                      [&](int a, int b) { return p_.gap0[a] < p_.gap0[b]; });
    for (int k = 0; k < margin; ++k) play_[open[k]] = 1;
    const int left_out = static_cast<int>(open.size()) - margin;
    if (count < std::max(8, m_ / 8) || left_out < std::max(48, m_ / 4)) play_.assign(m_, 1);
  }

  /// Settled sets on a condensation without some rows: their gaps on the whole displacement,
  /// and where the rule would hold one, those rows (and the open rows within a tenth of the
  /// largest closure of this solve) brought into play, held in `next`, for a condensation made
  /// again. False when every left-out row stays open.
  bool bring_into_play(ConstraintSolution& s, std::vector<char>& next) {
    if (all_in_play()) return false;
    complete_displacement(s);
    const VecX g = p_.gap0 + p_.gap_jacobian * s.u;
    const VecX sl = slip(s.u);
    std::vector<char> full = next;
    const std::vector<char> play = std::exchange(play_, {});
    update(s, g, sl, full);
    play_ = play;
    double closure = 0.0;
    for (int i = 0; i < m_; ++i)
      if (play_[i]) closure = std::max(closure, p_.gap0[i] - g[i]);
    bool brought = false;
    for (int i = 0; i < m_; ++i) {
      if (play_[i] || (!full[i] && !(g[i] < 0.1 * closure))) continue;
      play_[i] = 1;
      brought = true;
      for (const int k : {i, m_ + i, 2 * m_ + i}) next[k] = full[k];
    }
    // (a third time, every row: the condensation is not made again and again)
    if (brought && ++broadened_ == 3) play_.assign(m_, 1);
    return brought;
  }

  /// The method's rule: the next sets from the solution; returns the iteration's residual (the
  /// largest violation of the complementarity conditions, as a force).
  double update(const ConstraintSolution& sol, const VecX& g, const VecX& sl,
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

  IterationRecord record(int it, const std::vector<char>& code, const std::vector<char>& next,
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

  /// The solution's friction fields and active set from the last sets.
  void finish(const std::vector<char>& code, bool solved, ConstraintSolution& s) const {
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

  const ConstrainedProblem& p_;
  const RowMemory& memory_;  ///< where the sets start (cold_start, warm_start)
  const FrictionalOptions* o_ = nullptr;
  int n_, me_, m_;
  double s_;
  bool penalised_ = false;
  const SetRule* rule_ = nullptr;  ///< the rule in use (ssn's falls back on a cycle)
  PrimalDualRule primal_dual_;     ///< the rule of a caller that names none
  std::vector<char> binds_open_;  ///< per row: its law bounds it while open (Tresca)
  /// Per row: the pieces of its law seen so far (the sets name a piece by its number).
  mutable std::vector<std::vector<FrictionBound>> pieces_;
  std::vector<std::vector<std::pair<int, double>>> eq_rows_, gap_rows_, slip_rows_;
  VecX slip0_;  ///< the rows' slip at the start (zero without tangential rows)
  KktSolver kkt_;
  bool analysed_ = false;
  bool factored_ = false;                 ///< kkt_ holds the factor of factored_code_'s system
  std::vector<char> factored_code_;
  std::array<VecX, 3> factored_k_;        ///< and of these stiffnesses (penalised rows)
  /// The condensed path (null: LU only), its own or another caller's with these rows appended
  /// from first_row_ on (equality, normal, tangential).
  std::shared_ptr<SurfaceCondensation> surface_;
  int first_row_ = 0;
  bool surface_tried_ = false;
  /// Per gap row: in the condensation (empty: every row; see surface_ready()).
  std::vector<char> play_;
  int broadened_ = 0;                     ///< times bring_into_play() added rows
  /// Why the last solve failed where the LU's report does not say it (else empty), and the
  /// condensed block's message of the last failed condensed solve.
  std::string message_, surface_message_;
  core::SpdSolveReport counted_;          ///< the condensation's work counted so far
  double dense_counted_ = 0.0;
  bool surface_last_ = false;             ///< the last solve took the condensed path
  double surface_rcond_ = 1.0;            ///< its dense block's condition estimate
};

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
