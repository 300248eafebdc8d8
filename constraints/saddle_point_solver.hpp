// The saddle-point systems of the multiplier methods,
//
//   [ K        −s Cᵀ ] [ u ]   [ b_u ]       C = the equality rows A and the active gap rows G_A,
//   [ −s C      0    ] [ z ]ᵀ= [ b_c ]       z = multipliers / s,
//
// laid out as saddle_point_matrix() lays them out (with `all_rows`, inactive gap rows stay as
// s z_i = b_i). Two ways to solve them:
//
//  - Schur complement, when CHOLMOD can factorise K_ρ = K + C_Rᵀ diag(ρ) C_R and C has at most
//    a thousand rows. R is a fixed set of regularising rows (the equality rows and the 8 gap
//    rows nearest to closing; every row if those leave a rigid mode), ρ_r the row's local
//    stiffness, so a body held only by its contacts (K singular) needs no other path. K_ρ is
//    factorised once for the solver's lifetime; when rows first enter, W = K_ρ⁻¹ Cᵀ is solved
//    for them in blocks of 32 columns and reduced at once to their columns of S = C W over all
//    rows (kept; W is not, so memory stays O(n)). Each active set then costs a gather of the
//    small dense S, its LU, and two solves with K_ρ's factor. Rows of R in
//    the system are consistent (C_r u = its right-hand side, so ρ_r c_r c_rᵀ u moves to the
//    right-hand side); rows of R that are open get an auxiliary unknown ζ_r = ρ_r c_rᵀ u / s and
//    the diagonal −1/ρ_r in S. An active-set loop then costs one Cholesky plus a few solves:
//    contact at the price of a linear solve, floating body or not.
//    With every row's unknowns ordered last in K_ρ's factor (core::TailCholesky: the tail T,
//    when it has at most kMaxTail unknowns), S = Vᵀ V with V = L₂₂⁻¹ C_Tᵀ costs dense work on
//    the tail only, and a solve costs one forward substitution (kept while K_ρ's right-hand side
//    is: the active-set loop's is) and one back substitution: the multipliers come from the
//    tail's part of the forward solve, and the correction s K_ρ⁻¹ Cᵀ z stays on the tail until
//    the back substitution.
//  - LU of the whole saddle point (UMFPACK), when even K_ρ is singular or C is large; the
//    symbolic analysis is kept while the pattern is.
//
// Both report redundant constraint rows as singular (S's condition estimate, UMFPACK's rcond).
#pragma once

#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "constraints/constrained_problem.hpp"
#include "constraints/kkt_solver.hpp"
#include "core/spd_solver.hpp"
#include "core/tail_cholesky.hpp"

namespace c2d::constraints {

class SaddlePointSolver {
 public:
  /// `p` (K, A, G) is referenced and must outlive the solver; `s` is the row scale.
  SaddlePointSolver(const ConstrainedProblem& p, double s);
  ~SaddlePointSolver();
  SaddlePointSolver(const SaddlePointSolver&) = delete;
  SaddlePointSolver& operator=(const SaddlePointSolver&) = delete;

  /// Prepares the system of the gap rows marked in `active`. With `same_pattern` (all_rows and
  /// an unchanged K pattern) the LU path keeps its symbolic analysis.
  SolveStatus factorize(const std::vector<char>& active, bool all_rows, bool same_pattern);
  /// Call after changing p.stiffness: the Cholesky factor and W are recomputed on the next
  /// factorize().
  void stiffness_changed();
  /// Solves with the last factorisation; checks finiteness and the relative residual.
  /// With `surface_only`, on the condensed path: u only on the unknowns the rows touch (the
  /// rest zero), the multipliers exact, no back substitution; the report's residual is then the
  /// condensed system's (S z = r). An active-set loop needs no more until its set settles, and
  /// the full solve of the same right-hand side afterwards costs one back substitution.
  SolveStatus solve(const VecX& b, VecX& x, bool surface_only = false);
  /// True when solve(b, x, true) gives the surface-only solution (else it solves fully).
  bool condensed() const { return path_ == Path::kSchur && condensed_; }

  const KktSolveReport& report() const { return report_; }
  bool uses_schur() const { return path_ == Path::kSchur; }

 private:
  enum class Path { kUnknown, kSchur, kLu };
  SolveStatus factorize_schur();
  /// S = C K_ρ⁻¹ Cᵀ over the rows in the system, into `schur`: from the kept columns of S
  /// (solved with K_ρ's factor), or condensed, from V = L₂₂⁻¹ C_Tᵀ.
  SolveStatus schur_by_solves(Eigen::MatrixXd& schur);
  void schur_condensed(Eigen::MatrixXd& schur);
  /// The condensed solve: one forward substitution (kept while K_ρ's right-hand side is),
  /// dense work on the tail, one back substitution.
  SolveStatus solve_condensed(const VecX& b, VecX& x, bool surface_only = false);
  /// One step of iterative refinement of x with the condensed path's factors.
  SolveStatus refine(const VecX& b, VecX& x);
  /// The report's factorisation counts and times: the Cholesky's and the LU's, summed.
  void sync_report();
  /// Chooses R and ρ and factorises K_ρ; false when R cannot make K positive definite.
  bool factorize_regularised(int max_gap_rows);
  /// Schur path: K_ρ's right-hand side, with the rows of R in the system moved onto it.
  VecX regularised_rhs(const VecX& b) const;
  /// Solves K_ρ out = rhs; a failure goes into the report.
  SolveStatus solve_k_rho(const VecX& rhs, VecX& out);
  /// With every row in the system: the inactive gap rows' unknowns, s z_i = b_i.
  void solve_inactive_rows(const VecX& b, VecX& x) const;
  /// The multipliers z from the Schur complement, and y corrected to u; z's R-only rows zeroed.
  SolveStatus solve_multipliers(const VecX& b, VecX& y, VecX& z, VecX& x);
  /// The original rows' relative residual and the solution's finiteness, into the report.
  void check_solution(const VecX& b, const VecX& y, const VecX& z, VecX& x);

  const ConstrainedProblem& p_;
  double s_;
  Path path_ = Path::kUnknown;
  bool all_rows_ = false;
  core::SpdSolver chol_{core::SpdSolver::Backend::kCholmod, false};
  /// K_ρ's factor with every unknown a constraint row touches ordered last (the condensed path,
  /// taken when that tail is small enough for a dense L₂₂).
  core::TailCholesky tail_;
  bool condensed_ = false;
  std::vector<int> tail_dofs_;      ///< unknowns any constraint row touches
  std::vector<VecX> v_;             ///< L₂₂⁻¹ c_j (tail order); empty until j is in the system
  VecX cached_rhs_, cached_forward_;  ///< K_ρ's last right-hand side and its forward solve
  double dense_seconds_ = 0;        ///< the condensed path's dense work on the tail
  KktSolver lu_;
  SpMat ct_;                        ///< Cᵀ of every row, n × (m_eq + m): equality rows first
  std::vector<VecX> s_columns_;     ///< C K_ρ⁻¹ c_j over every row; empty until j is in the system
  std::vector<int> rows_;           ///< constraint indices in the current system
  std::vector<int> positions_;      ///< their positions in the saddle-point vector
  int size_ = 0;                    ///< saddle-point vector length
  SpMat c_rows_;                    ///< C_rows
  Eigen::PartialPivLU<Eigen::MatrixXd> schur_;
  Eigen::MatrixXd schur_matrix_;    ///< S itself (condensed path: the surface-only residual)
  /// Regularisation: ρ per constraint (0 = not in R); sized me + m, empty without.
  VecX rho_;
  SpMat k_rho_;                     ///< K_ρ, factorised in chol_
  std::vector<char> in_rows_;       ///< per system row: 1 for a row of the problem, 0 for R-only
  KktSolveReport report_;
};

}  // namespace c2d::constraints
