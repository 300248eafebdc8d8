// Machinery the backends share: the penalised (augmented-Lagrangian) inner solve, the
// saddle-point system, tolerances, and the final checks every solution passes through.
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "constraints/active_set_tracker.hpp"
#include "constraints/constraint_strategy.hpp"
#include "constraints/set_rules.hpp"
#include "constraints/surface_condensation.hpp"
#include "core/spd_solver.hpp"

namespace c2d::constraints {

/// Penetration tolerance: the absolute option, else relative × `length_scale` (the shortest
/// contact edge).
double penetration_tolerance(const StrategyOptions& options, double length_scale);
/// The same at the problem's length scale.
double penetration_tolerance(const StrategyOptions& options, const ConstrainedProblem& p);

/// Rows closed at the start: the memory's warm start if it has one, else the rows with
/// g0 ≤ 1e-12 × model size (touching or already penetrating).
std::vector<char> initially_closed(const ConstrainedProblem& p, const RowMemory& memory);

/// The margins a set rule compares with: 1e-10 of `force_scale` (the largest force; at least
/// of c × the touch tolerance), the touch tolerance for gaps, and c.
RuleScales rule_scales(const ConstrainedProblem& p, double force_scale, double c);

/// A frictionless set iteration's next set from the rule: `next` holds the current set on entry
/// and the rule's decisions on return; `penalty` and `estimate` are a regularised rule's k and
/// λ̂ (empty for an exact rule); c is the semi-smooth rule's. Returns the largest violation of
/// the complementarity conditions.
double next_normal_set(const SetRule& rule, const ConstrainedProblem& p, const VecX& force,
                       const VecX& gap, const VecX& penalty, const VecX& estimate, double c,
                       std::vector<char>& next);

/// The history record of one active-set iteration that produced `next`.
IterationRecord make_record(int iteration, const std::vector<char>& next,
                            const ActiveSetTracker::Change& change, const VecX& gap,
                            double residual);

/// Whether an active-set iteration is settling: it is not when this many iterations in a row
/// change the set without reaching a new fewest number of changing rows (the full-step
/// iteration on a slender body wanders like that for dozens of iterations).
class StallMonitor {
 public:
  bool progress(const ActiveSetTracker::Change& change) {
    const int changes = change.entering + change.leaving;
    if (changes < fewest_) {
      fewest_ = changes;
      since_fewest_ = 0;
      return true;
    }
    return ++since_fewest_ < kStallIterations;
  }

 private:
  static constexpr int kStallIterations = 3;
  int fewest_ = std::numeric_limits<int>::max();
  int since_fewest_ = 0;
};

/// Fills gap, max penetration and equality violation from u; turns any non-finite result into
/// a failed status with zeroed fields, so no NaN leaves a backend.
void finish_solution(const ConstrainedProblem& p, ConstraintSolution& s);

/// Adds the linear-solver work one solution recorded (factorisations, symbolic analyses and
/// the seconds of each phase) to another's: a first attempt's or a crossover's, kept with the
/// solution that is returned.
void add_solution_work(const ConstraintSolution& from, ConstraintSolution& to);

/// Adds a solver's work between two of its reports (`before`, then `now`) to s's figures: a
/// method that calls a kept solver repeatedly sums each call's share.
template <class Report>
void add_solver_work(const Report& now, const Report& before, ConstraintSolution& s) {
  s.factorizations += now.numeric_factorizations - before.numeric_factorizations;
  s.symbolic_analyses += now.symbolic_analyses - before.symbolic_analyses;
  s.symbolic_seconds += now.symbolic_seconds - before.symbolic_seconds;
  s.numeric_seconds += now.numeric_seconds - before.numeric_seconds;
  s.solve_seconds += now.solve_seconds - before.solve_seconds;
}

/// Solves the equality problem of the gap rows marked in a set: fills u, λ (0 off the set; a
/// row of the set may be in tension) and μ, or returns a failed status with a message.
using SetSolve = std::function<SolveStatus(const std::vector<char>& set, ConstraintSolution& s,
                                           std::string& message)>;

/// The safeguard of the active-set iterations when theirs cycles or wanders: a dual active-set
/// method (Goldfarb and Idnani's, each set's system solved afresh through `solve_set`). From
/// `active` it drops the rows in tension until every force is ≥ 0, then adds the most violated
/// row q (g_q − shift_q < −touch tolerance; shift = λ̂/k for penalised rows, 0 for exact ones)
/// along the straight path from the current state to the solution of A ∪ {q}: λ_q grows, and
/// where a force of A would turn negative the step stops and that row leaves. Every state has
/// λ ≥ 0 and the dual objective grows at each step, so no set returns and the number of steps
/// is finite. `s` holds the last state and gets one history record per step, numbered after
/// `iteration`; `active` the last set. Returns converged, or the status and `message` of what
/// stopped it (a failed solve, a redundant row, `max_steps`).
SolveStatus dual_active_set(const ConstrainedProblem& p, const SetSolve& solve_set,
                            const VecX& shift, int max_steps, int iteration,
                            std::vector<char>& active, ConstraintSolution& s, std::string& message);

/// Scale that brings constraint rows to the magnitude of K's entries (mean of diag K).
double saddle_point_scale(const ConstrainedProblem& p);

/// Position of each multiplier in the saddle-point vector (−1: not in the system); `size`
/// gets the system's size.
std::vector<int> gap_positions(const ConstrainedProblem& p, const std::vector<char>& active,
                               bool all_rows, int& size);

/// The saddle-point matrix for the multipliers of the equality rows and of the inequality rows
/// with `active` set:
///   [ K      −s Aᵀ   −s G_Aᵀ ]
///   [ −s A    0       0      ]
///   [ −s G_A  0       0      ]
/// With `all_rows`, inactive rows stay in the system as λ_i = 0 (a unit diagonal s, the G entries
/// kept as structural zeros), so the pattern never changes; otherwise they are left out.
SpMat saddle_point_matrix(const ConstrainedProblem& p, const std::vector<char>& active, double s,
                          bool all_rows);
/// Right-hand side [f; −s b; s g0_A] of the same system.
VecX saddle_point_rhs(const ConstrainedProblem& p, const std::vector<char>& active, double s,
                      bool all_rows);

}  // namespace c2d::constraints
