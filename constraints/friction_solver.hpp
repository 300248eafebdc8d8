// The set iteration of contact, 2D Coulomb or Tresca friction or none: one active-set iteration
// on the rows' complementarity conditions, whose rules are the method's. It solves every
// method's problems, with friction and without (a frictionless problem has no tangential rows):
// lagrange's and ssn's, the penalty-type methods' (their rows compliances 1/k, each penalty
// raise or multiplier round a new dense block on the same factor), ipopt's crossover.
//
// Every row is one of three kinds, with a multiplier scaled by s (z = λ / s):
//   equality rows   c = A u − b      force  Aᵀμ
//   normal rows     c = g0 + G u     force  Gᵀλ      (λ ≥ 0 compressive)
//   tangential rows c = −(s0 + T u)  force −Tᵀλ_t    (λ_t opposes the slip s = s0 + T u)
// and a row is held (c = 0 exactly, or λ = λ̂ − k c for a penalised one), free (λ = 0), or, for a
// tangential row, slipping: λ_t = σ μ λ (Coulomb) or σ b (Tresca), σ = ±1 the slip's sign. In
// 2D, with σ fixed, that slip condition is linear in the multipliers, so each iteration solves
// one linear system, exactly the semi-smooth Newton step of the frictional complementarity
// functions (Hüeber, Stadler and Wohlmuth, SISC 2008): K u − s Cᵀ z = f with the rows' equations,
// non-symmetric through the slip rows' coupling to their normal multiplier: condensed onto the
// rows (surface_condensation.hpp: K factorised once, a small dense block per set), or, where K
// does not factorise, the whole saddle point by UMFPACK with one symbolic analysis (every row
// keeps its entries, zero when unused).
//
// The rules that choose the next sets from the new λ, λ_t, g and s are the method's
// (constraints/set_rules.hpp: primal-dual, semi-smooth, return map); this iteration asks the
// rule for every row and records the sets in the one cycle detector (ActiveSetTracker). The
// iteration ends when the sets repeat (converged), return to an earlier combination (cycling)
// or reach the iteration limit; each is a named status. Where a rule without globalisation
// cycles (the semi-smooth step), its fallback (the primal-dual rule, its limit c → 0)
// continues from those sets; a warm start that cycles is dropped for the cold one. Without
// friction, an exact rule whose sets still cycle, or stop settling (StallMonitor), is finished
// by the dual active-set safeguard on the same factor (strategy_common.hpp).
//
// Rows in play. The condensation takes only the rows that may carry force in this solve: the
// held and closed ones, those within the load step's closing reach (RowMemory) and a margin
// of the nearest open ones. The rest stay free and out of the dense tail (its factor costs the
// cube of its size); once the sets settle their gaps are read on the whole displacement, and a
// row the rule would hold brings them into a condensation made again.
#pragma once

#include <memory>
#include <string>

#include "constraints/constrained_problem.hpp"

namespace c2d::constraints {

class SetRule;
class SurfaceCondensation;

struct FrictionalOptions {
  /// The method's rule (null: the primal-dual rule). A regularised rule (the return map) makes
  /// every row compliant with the stiffnesses below.
  const SetRule* rule = nullptr;
  /// Regularised rules: the stiffness of each gap, tangential and equality row, and the multiplier
  /// estimates λ̂, λ̂_t, μ̂ (the augmented Lagrangian's; the penalty's λ̂_t is the elastic
  /// tangential force of the last converged state, λ̂ and μ̂ are 0). Ignored by the exact rules.
  VecX k_gap, k_tangent, k_eq;
  VecX lambda_hat, tangent_hat, mu_hat;
  int max_iterations = 50;
  /// Optional starting sets: a solution's active rows held, its friction states, a slipping
  /// row's direction from the sign of its friction force (null: the memory's warm start, every
  /// closed frictional row sticking).
  const ConstraintSolution* start = nullptr;
  /// Number of the first iteration in the history (a method that calls repeatedly numbers on).
  int first_iteration = 1;
  /// A frictionless exact iteration that cycles or stops settling is finished by the dual
  /// active-set safeguard (strategy_common.hpp); off for a crossover that only confirms.
  bool safeguard = true;
};

class FrictionalSolve;

/// The solver of one problem, kept across calls: a call whose sets and stiffnesses repeat the
/// last factorised system's (an augmented Lagrangian's multiplier update) reuses its factor.
/// Its sets start from `memory` (the rows it gives closed, their law's pieces at its forces,
/// its friction states), or from a solution a call gives (FrictionalOptions::start).
class FrictionalSolver {
 public:
  /// `p` and `memory` must outlive the solver.
  FrictionalSolver(const ConstrainedProblem& p, const RowMemory& memory);
  ~FrictionalSolver();
  FrictionalSolver(const FrictionalSolver&) = delete;
  FrictionalSolver& operator=(const FrictionalSolver&) = delete;
  /// As solve_frictional().
  void solve(const FrictionalOptions& options, ConstraintSolution& s);
  /// Solves on `surface`, a condensation of the problem's K made for another caller (its rows
  /// regularising as they do there; this solver's rows appended), instead of factorising K
  /// itself: ipopt's crossover on its dual's factor. False, and the solver unchanged, when the
  /// rows cannot be appended (they touch unknowns outside its tail; it holds anchor rows) or
  /// the solver has already chosen its path.
  bool share(const std::shared_ptr<SurfaceCondensation>& surface);

 private:
  std::unique_ptr<FrictionalSolve> impl_;
};

/// Solves the frictional problem with the method's rule: fills u, λ, λ_t, μ, the slip, the
/// friction states, the active set, the history and the status (never throws; a failed or
/// stopped solve keeps its last state with λ ≥ 0, or zeros when no system was solved).
/// `s.history` is appended to.
void solve_frictional(const ConstrainedProblem& p, const RowMemory& memory,
                      const FrictionalOptions& options, ConstraintSolution& s);

/// The same for an exact rule (primal-dual, semi-smooth) from the memory's warm start.
ConstraintSolution solve_frictional(const ConstrainedProblem& p, const RowMemory& memory,
                                    const SetRule& rule, int max_iterations);

/// The crossover of a method whose own iteration identifies the sets (ipopt's interior point,
/// auglag's multiplier rounds): the sets of `s` (its active rows, friction states, a slipping
/// row's direction from the sign of its friction force) solved exactly on `solver`'s factor and
/// confirmed by the primal-dual rule, whose exact solution must reproduce them (which checks
/// every complementarity condition of the Coulomb problem), within `max_solves` solves. True
/// with s the exact solution (the solves appended to its history, their work added); otherwise
/// s keeps its own solution (the work still added) and `why` says what the exact solves found.
bool confirm_exactly(FrictionalSolver& solver, int max_solves, ConstraintSolution& s,
                     std::string& why);

/// The tangential stiffness of penalty-type methods: k_t = ratio × k per row.
VecX tangent_penalties(const ConstrainedProblem& p, const VecX& k_gap);

}  // namespace c2d::constraints
