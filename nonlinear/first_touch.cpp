#include "nonlinear/first_touch.hpp"

#include <algorithm>
#include <limits>
#include <utility>

#include "constraints/strategy_common.hpp"

namespace c2d::nonlinear {

using namespace c2d::constraints;

namespace {

/// Solves after the first singular one, each with the next nearest rows closed.
constexpr int kFirstTouchAttempts = 3;
/// Rows this near to touching (a fraction of the smallest contact edge) are guessed closed.
constexpr double kNearlyTouching = 1e-2;

/// Closes, in `memory`'s initial active set, the open rows nearest to touching (gap within the
/// touch tolerance of the smallest open gap) when that gap is at most `within`; the rows already
/// closed stay closed, and rows on prescribed DOFs only cannot be closed. Returns whether it
/// closed any.
bool close_nearest(const ConstrainedProblem& qp, double within, RowMemory& memory) {
  const int m = qp.num_gaps();
  std::vector<char> free(m, 0);
  for (int k = 0; k < qp.gap_jacobian.outerSize(); ++k)
    for (SpMat::InnerIterator it(qp.gap_jacobian, k); it; ++it) free[it.row()] = 1;
  double nearest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < m; ++i)
    if (free[i] && !memory.initial_active[i]) nearest = std::min(nearest, qp.gap0[i]);
  if (!(nearest <= within)) return false;
  const double touch = touch_tolerance(qp);
  for (int i = 0; i < m; ++i)
    memory.initial_active[i] = memory.initial_active[i] || (free[i] && qp.gap0[i] <= nearest + touch);
  return true;
}

}  // namespace

void warm_start(const ConstrainedProblem& qp, const std::vector<GapRow>& rows,
                const std::vector<char>& previous, const std::vector<double>& force_by_slot,
                RowMemory& memory) {
  const int m = qp.num_gaps();
  memory.initial_active.assign(m, 0);
  memory.initial_force = VecX::Zero(m);
  const double touch = touch_tolerance(qp);
  bool any = false;
  if (qp.has_friction()) memory.initial_friction.assign(m, 0);
  for (int i = 0; i < m; ++i) {
    if (qp.has_friction()) memory.initial_friction[i] = previous[rows[i].slot];
    memory.initial_active[i] = previous[rows[i].slot] || qp.gap0[i] <= touch;
    memory.initial_force[i] = force_by_slot[rows[i].slot];
    any = any || memory.initial_active[i];
  }
  // A body held only by its contact (a cylinder on a floor) is otherwise singular in the first
  // solve; a wrong guess costs one active-set iteration. Node rows at a first touch have gap 0,
  // but a mortar row's gap is a mean under its hat, positive on a curved surface. Farther rows
  // are closed only when the open solve is singular (solve_catching_first_touch).
  if (!any) close_nearest(qp, kNearlyTouching * qp.length_scale, memory);
}

ConstraintSolution solve_catching_first_touch(ConstraintStrategy& strategy,
                                              const ConstrainedProblem& qp, RowMemory& memory) {
  ConstraintSolution s = strategy.solve(qp, memory);
  // Singular with the rows it started from: the next nearest rows close and the method solves
  // again, a few times at most. With every row open, the nearest catch a body held only by its
  // contact; with a few closed, the next ones hold what those leave free (a pin first touching
  // a conformal hole at one node turns about it, held by friction only where rows stick).
  const bool none_closed = std::none_of(memory.initial_active.begin(), memory.initial_active.end(),
                                        [](char a) { return a; });
  const double within = none_closed ? std::numeric_limits<double>::infinity()
                                    : kNearlyTouching * qp.length_scale;
  for (int attempt = 0; attempt < kFirstTouchAttempts && s.status == SolveStatus::kSingular;
       ++attempt) {
    if (!close_nearest(qp, within, memory)) break;
    const ConstraintSolution failed = std::move(s);
    s = strategy.solve(qp, memory);
    add_solution_work(failed, s);  // the singular attempts' work counts too
    s.iterations += failed.iterations;
    s.seconds += failed.seconds;
  }
  return s;
}

}  // namespace c2d::nonlinear
