// The pieces of the ipopt method (ipopt_strategy.cpp) that its friction (ipopt_friction.cpp)
// shares: the QP's rows as Ipopt sees them, one Ipopt solve, and the reading of its forces.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "constraints/constraint_strategy.hpp"

namespace c2d::constraints::ipopt_detail {

/// A constraint row kept for Ipopt: normalised coefficients, bounds, and where it came from.
struct KeptRow {
  std::vector<std::pair<int, double>> terms;
  double lower = 0, upper = 0, norm = 1;
  bool equality = false;
  int source = 0;  ///< index into the problem's equality or gap rows
};

struct RowSet {
  std::vector<KeptRow> rows;
  int dropped_zero = 0, dropped_duplicate = 0;
  std::string inconsistent;  ///< non-empty: contradictory duplicate rows
};

/// Normalises the rows and drops zero rows and duplicates (the tightest copy of a gap row is
/// kept; duplicate equalities must agree).
RowSet prepare_rows(const ConstrainedProblem& p);

struct QpOutcome {
  SolveStatus status = SolveStatus::kFailed;
  std::string message;
  VecX x, lambda;  ///< [u; p] and Ipopt's multipliers of the rows
  int iterations = 0;
};

/// Ipopt on the QP of `rows` over x = [u; p] with auxiliary costs `cost` (empty: none).
QpOutcome run_ipopt(const ConstrainedProblem& p, const RowSet& rows, const VecX& cost,
                    const StrategyOptions& o, double tolerance);

/// Forces from Ipopt's multipliers (its Lagrangian is f + gᵀλ: a row exerts −λ / |row|): the
/// gap rows' λ ≥ 0, the equality rows' μ, and λ_t from the friction rows (`friction_sign` per
/// row: 0 none, ±1 a Tresca face, 2 a sticking equality).
void extract_forces(const ConstrainedProblem& p, const RowSet& rows,
                    const std::vector<int>& friction_sign, const QpOutcome& qp,
                    ConstraintSolution& s);

/// The rows of an interior-point solution that carry force (above 1e-6 of the largest) and
/// touch (gap within the penetration tolerance): the others' forces are the barrier's O(μ/gap).
std::vector<char> touching_rows(const ConstrainedProblem& p, const StrategyOptions& o,
                                const ConstraintSolution& s);

/// The active rows of an interior-point solution, and (with `check_rigid_motion`) whether the
/// rows that hold it leave a rigid motion free (then status singular).
void settle_active_set(const ConstrainedProblem& p, const StrategyOptions& o,
                       ConstraintSolution& s, bool check_rigid_motion = true);

/// Friction: the fixed point of Tresca problems (ipopt_friction.cpp), which ends as soon as a
/// QP's sets pass the crossover (`exact`: s is then the exact solution of those sets). Fills s
/// (its history and status), the QP iterations, and the last bounds; returns the message.
std::string solve_tresca_fixed_point(const ConstrainedProblem& p, const StrategyOptions& o,
                                     const RowSet& base, ConstraintSolution& s,
                                     int& total_iterations, VecX& bound, bool& exact);

/// After the fixed point: unless it ended exact, the active rows, each one's stick or slip
/// (slip where its force reached the bound, to 1e-6) and the crossover that solves those sets
/// exactly; then the check that the rows holding the solution (sticking ones along t too) leave
/// no rigid motion free.
void finish_friction(const ConstrainedProblem& p, const StrategyOptions& o, const VecX& bound,
                     bool exact, ConstraintSolution& s);

}  // namespace c2d::constraints::ipopt_detail
