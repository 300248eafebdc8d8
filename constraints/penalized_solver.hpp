// The penalised (augmented-Lagrangian) inner solve of penalty, adaptive_penalty and auglag, on
// K condensed onto the contact surface.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "constraints/strategy_common.hpp"
#include "constraints/surface_condensation.hpp"
#include "core/spd_solver.hpp"

namespace c2d::constraints {

/// Minimises ½uᵀKu − fᵀu + Σ_i (1/2k_i) max(0, λ_i − k_i g_i(u))² − μᵀh(u) + ½ Σ_j k_j h_j(u)²
/// (h = A u − b) for fixed λ, μ: with λ = μ = 0 the pure penalty method, otherwise one
/// augmented-Lagrangian subproblem. The max() makes it semi-smooth; an active-set loop solves it
/// exactly once the set settles; when it cycles or stops settling, dual_active_set() finishes.
/// Each set's system K u = f + Gᵀ w + Aᵀ w_eq, with w = λ − k g on the closed rows and
/// w_eq = μ − k_eq h, is solved on K condensed onto the rows (SurfaceCondensation: K, regularised
/// where a body is held only by its rows, factorised once for the solver's lifetime; each set,
/// penalty and multiplier estimate then costs dense work on the rows, the rows' compliances 1/k
/// on the diagonal). When the rows do not fit a dense block, or that path fails, the assembled
/// K + Gᵀ diag(k·active) G + Aᵀ diag(k_eq) A is factorised instead (one pattern, so CHOLMOD's
/// symbolic analysis is reused across iterations and calls).
class PenalizedSolver {
 public:
  /// `rule` chooses each iteration's set (the method's return map).
  PenalizedSolver(const ConstrainedProblem& p, const SetRule& rule);

  struct Outcome {
    SolveStatus status = SolveStatus::kFailed;
    std::string message;
    int iterations = 0;
  };
  /// `active` is the starting set on entry and the final set on return; `history` gets one
  /// record per inner iteration, numbered from `first_iteration`.
  Outcome solve(const VecX& k_gap, const VecX& lambda, const VecX& k_eq, const VecX& mu,
                int max_iterations, std::vector<char>& active, VecX& u,
                std::vector<IterationRecord>& history, int first_iteration);

  /// The solution's factorisation counts and times (both paths'), and the pivot ratio of the
  /// last factor used: K_ρ's on the condensed path, K + Gᵀ k G's on the assembled one.
  void report_counts(ConstraintSolution& s) const;
  /// The forces of the state the last solve() returned into s (contact_force, active,
  /// eq_multiplier, penalty, eq_penalty): a condensed solve's own forces w (exact to the dense
  /// block's precision), else λ = max(0, λ̂ − k g) and μ = μ̂ − k h from s.u, which carry the
  /// gaps' round-off times k.
  void forces(const VecX& k_gap, const VecX& lambda, const VecX& k_eq, const VecX& mu,
              ConstraintSolution& s) const;
  /// How far the forces that the penalty's equations give from u, λ̂ − k g and μ̂ − k h, stand
  /// from the condensed solve's own forces at the state solve() returned: the measured
  /// round-off that k lends them (largest over the held rows). 0 without a condensed state.
  double force_round_off(const VecX& k_gap, const VecX& lambda, const VecX& k_eq,
                         const VecX& mu, const VecX& u) const;
  /// The largest ratio, over the rows carrying force w (above 1e-6 of the largest), of a gap's
  /// round-off, 16 ε (|g0| + Σ|G_ij u_j|), to the penetration w/k that the penalty leaves it:
  /// above 1 the penetration is below what the gaps resolve, so the set decisions read noise.
  double unresolved_penetration(const VecX& force, const VecX& k_gap, const VecX& u) const;
  /// Whether the last solve took the condensed path (its forces then owe nothing to the
  /// penalty's conditioning).
  bool condensed() const { return surface_last_; }

 private:
  /// The gaps g = g0 + G u at u (empty without gap rows).
  VecX gaps(const VecX& u) const;
  /// The penalised forces at u of every gap row, λ − k g(u), and of the equality rows,
  /// μ − k_eq (A u − b) (empty without such rows).
  VecX penalised_gap_forces(const VecX& u, const VecX& k_gap, const VecX& lambda) const;
  VecX penalised_eq_forces(const VecX& u, const VecX& k_eq, const VecX& mu) const;

  /// Solves the penalised system with the rows of `set` closed: K + Gᵀ k G over the set
  /// (+ Aᵀ k A), right-hand side f + Gᵀ(λ̂ − k g0) over the set (+ the equalities'). With
  /// `tail_only` a condensed solve leaves u on the unknowns the rows touch (all the set
  /// decisions read); complete() then gives the whole.
  SolveStatus solve_set(const std::vector<char>& set, const VecX& k_gap, const VecX& lambda,
                        const VecX& k_eq, const VecX& mu, const VecX& rhs_eq, VecX& u,
                        bool tail_only);
  /// The condensed path: K_ρ factorised on first use; false when the rows do not fit it.
  bool surface_ready();
  SolveStatus solve_condensed(const std::vector<char>& set, const VecX& k_gap,
                              const VecX& lambda, const VecX& k_eq, const VecX& mu, VecX& u,
                              bool tail_only);
  /// The whole u of the last solve (a condensed one's tail only until then), refined with the
  /// same factors while the penalised equations' residual exceeds 1e-12 of the forces (a
  /// slender body's K_ρ loses digits; at most three steps, each kept only when it gains).
  void complete(VecX& u);
  /// The penalised equations' residual at (u, w): K u − f − Cᵀ w, and per held row
  /// k (target − c·u) − w (a force); returns its largest entry over the force scale.
  double residual(const VecX& u, const VecX& w, VecX& r_u, VecX& r_rows) const;

  const ConstrainedProblem& p_;
  const SetRule& rule_;
  SpMat gt_, at_;  ///< Gᵀ and Aᵀ
  std::unique_ptr<SurfaceCondensation> surface_;  ///< the condensed path (null: assembled)
  bool surface_tried_ = false;
  bool surface_last_ = false;  ///< the last solve took the condensed path
  VecX last_w_;                ///< its row forces (equalities first, then gaps)
  SurfaceCondensation::RowStates last_states_;  ///< and its rows' states
  VecX kept_w_;                ///< the forces of the state solve() returned (empty: from u)
  core::SpdSolver solver_;
  /// The factorised matrix and what it was built from: a solve whose set and stiffnesses repeat
  /// them (an augmented Lagrangian's multiplier update) needs a new right-hand side only.
  SpMat kp_;
  std::vector<char> factored_set_;
  VecX factored_k_gap_, factored_k_eq_;
  bool factored_ = false;
};

}  // namespace c2d::constraints
