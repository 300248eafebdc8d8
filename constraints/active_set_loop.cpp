// The active-set loop of the exact multiplier methods (lagrange, ssn) on one set of rows: the
// saddle-point right-hand side, the split of its solution, and the loop with its safeguard.
#include <algorithm>
#include <string>
#include <vector>

#include "constraints/saddle_point_solver.hpp"
#include "core/interrupt.hpp"
#include "constraints/strategy_common.hpp"

namespace c2d::constraints {

VecX saddle_point_rhs(const ConstrainedProblem& p, const std::vector<char>& active, double s,
                      bool all_rows) {
  const int n = p.num_unknowns(), me = p.num_equalities();
  int size = 0;
  const auto pos = gap_positions(p, active, all_rows, size);
  VecX b = VecX::Zero(size);
  b.head(n) = p.load;
  if (me > 0) b.segment(n, me) = -s * p.eq_rhs;
  for (int i = 0; i < p.num_gaps(); ++i)
    if (pos[i] >= 0 && active[i]) b[pos[i]] = s * p.gap0[i];
  return b;
}

void split_saddle_point(const ConstrainedProblem& p, const std::vector<char>& active, double s,
                        bool all_rows, const VecX& x, ConstraintSolution& out) {
  const int n = p.num_unknowns(), me = p.num_equalities();
  int size = 0;
  const auto pos = gap_positions(p, active, all_rows, size);
  out.u = x.head(n);
  out.eq_multiplier = me > 0 ? VecX(s * x.segment(n, me)) : VecX();
  out.contact_force = VecX::Zero(p.num_gaps());
  for (int i = 0; i < p.num_gaps(); ++i)
    if (pos[i] >= 0 && active[i]) out.contact_force[i] = s * x[pos[i]];
}

namespace {

/// The saddle-point solves of an active-set loop: one factorisation per set, the solution split
/// into u, μ and λ. On the condensed path a surface-only solve gives u only where the rows
/// reach (all the loop reads until its set settles); complete() then solves the set fully.
class SetSolver {
 public:
  SetSolver(const ConstrainedProblem& p, bool all_rows)
      : p_(p), all_rows_(all_rows), scale_(saddle_point_scale(p)), kkt_(p, scale_) {}
  SolveStatus solve(const std::vector<char>& set, ConstraintSolution& out, std::string& error,
                    bool surface_only) {
    VecX x;
    SolveStatus st = SolveStatus::kConverged;
    if (!analysed_ || set != factorized_) {
      st = kkt_.factorize(set, all_rows_, all_rows_ && analysed_);
      analysed_ = true;
      factorized_ = set;
    }
    if (st == SolveStatus::kConverged)
      st = kkt_.solve(saddle_point_rhs(p_, set, scale_, all_rows_), x, surface_only);
    if (st == SolveStatus::kConverged)
      split_saddle_point(p_, set, scale_, all_rows_, x, out);
    else
      error = kkt_.report().message;
    return st;
  }
  SetSolve as_set_solve(bool surface_only) {
    return [this, surface_only](const std::vector<char>& set, ConstraintSolution& out,
                                std::string& error) { return solve(set, out, error, surface_only); };
  }
  /// `s` as the full solution of `set` after surface-only solves (one back substitution).
  SolveStatus complete(const std::vector<char>& set, ConstraintSolution& s, std::string& error) {
    return kkt_.condensed() ? solve(set, s, error, false) : SolveStatus::kConverged;
  }
  const SaddlePointSolver& kkt() const { return kkt_; }

 private:
  const ConstrainedProblem& p_;
  bool all_rows_;
  double scale_;
  SaddlePointSolver kkt_;
  bool analysed_ = false;
  std::vector<char> factorized_;  ///< the set of the last factorisation
};

}  // namespace

void solve_active_set(const ConstrainedProblem& p, const RowMemory& memory, int max_iterations,
                      bool all_rows, const NextActiveSet& next_set, const std::string& step,
                      ConstraintSolution& s) {
  std::vector<char> active = initially_closed(p, memory);
  ActiveSetTracker tracker;
  tracker.record(active);
  StallMonitor stall;
  SetSolver sets(p, all_rows);
  s.status = SolveStatus::kMaxIterations;
  std::string why =
      "active set still changing after " + std::to_string(max_iterations) + " " + step + "s";
  for (int it = 1; it <= max_iterations; ++it) {
    core::check_interrupt();
    if (const SolveStatus st = sets.solve(active, s, s.message, true);
        st != SolveStatus::kConverged) {
      s.status = st;
      s.iterations = it;
      break;
    }
    const VecX g = p.num_gaps() > 0 ? VecX(p.gap0 + p.gap_jacobian * s.u) : VecX();
    std::vector<char> next = active;
    const double residual = next_set(s, g, sets.kkt().report().relative_residual, next);
    const auto change = tracker.record(next);
    s.history.push_back(make_record(it, next, change, g, residual));
    if (change.unchanged) {
      s.status = sets.complete(active, s, s.message);
      if (s.status == SolveStatus::kConverged) s.message.clear();
      break;
    }
    if (change.repeated) {
      s.status = SolveStatus::kCycling;
      why = "active set returned to an earlier set at " + step + " " + std::to_string(it);
      break;
    }
    if (!stall.progress(change)) {
      why = "active set not settling after " + std::to_string(it) + " " + step + "s";
      break;
    }
    active = next;
  }
  if (s.status == SolveStatus::kCycling || s.status == SolveStatus::kMaxIterations) {
    // The set cycles or wanders: the safeguard finishes from the last set, or names why not.
    // It ends on a set's own solution (or stops short of one); either way that set is solved
    // fully, so that u is whole (forces held compressive when it converged).
    std::string message;
    const int last = s.history.empty() ? 0 : s.history.back().iteration;
    s.status = dual_active_set(p, sets.as_set_solve(true), VecX::Zero(p.num_gaps()),
                               max_iterations + 2 * p.num_gaps(), last, active, s, message);
    ConstraintSolution whole = s;
    std::string unused;
    if (sets.complete(active, whole, unused) == SolveStatus::kConverged) {
      s.u = whole.u;
      s.eq_multiplier = whole.eq_multiplier;
      s.contact_force = whole.contact_force;
      if (s.status == SolveStatus::kConverged) s.contact_force = s.contact_force.cwiseMax(0.0);
    }
    s.message = s.status == SolveStatus::kConverged ? "" : why + "; " + message;
  }
  s.active = active;
  copy_solver_figures(sets.kkt().report(), s);
  s.pivot_ratio = sets.kkt().report().rcond;
  if (s.status != SolveStatus::kConverged && s.status != SolveStatus::kCycling &&
      s.status != SolveStatus::kMaxIterations) {
    s.u = VecX::Zero(p.num_unknowns());
    s.contact_force = VecX::Zero(p.num_gaps());
  }
  // A state that stopped short reports no tension: a row in tension carries no force.
  if (s.status != SolveStatus::kConverged && s.contact_force.size() == p.num_gaps())
    s.contact_force = s.contact_force.cwiseMax(0.0);
}

}  // namespace c2d::constraints
