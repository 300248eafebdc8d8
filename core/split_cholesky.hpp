// Cholesky factorisation of a stiffness matrix split in two halves, factorised side by side.
//
// A split of the unknowns (FillOrder::part) into halves A, B and a separator S with K_AB = 0
// gives each half h a matrix of its own, the separator ordered last:
//
//   M_h = [ K_hh  K_hS ] = L_h L_hᵀ,   L_h = [ L_hh    0    ],   L_SSʰ L_SSʰᵀ = K_SS − K_Sh K_hh⁻¹ K_hS,
//         [ K_Sh  K_SS ]                     [ L_Sh  L_SSʰ  ]
//
// (M_h is a principal submatrix of K, so positive definite with K). The two factorisations run
// on two threads, and the separator's Schur complement of K follows from their trailing blocks:
//
//   S = K_SS − Σ_h K_Sh K_hh⁻¹ K_hS = L_SSᴬ L_SSᴬᵀ + L_SSᴮ L_SSᴮᵀ − K_SS,   dense, |S| × |S|.
//
// A solve K x = b is a forward substitution per half, L_h wʰ = [b_h; 0]; the separator's
// S x_S = b_S + Σ_h L_SSʰ w_Sʰ (since K_Sh K_hh⁻¹ b_h = L_Sh w_hʰ = −L_SSʰ w_Sʰ); and a back
// substitution per half, L_hᵀ y = [w_hʰ; L_SSʰᵀ x_S], whose first rows are x_h.
//
// CHOLMOD's supernodal factorisation uses a second core only inside its BLAS calls on the
// larger fronts (1.06M-DOF T6 grid: about 10 % faster on two cores than on one); the split
// gives each core half the elimination tree. Measured on a 981,400-DOF T6 grid: analysis +
// numeric 5.0 s whole, 3.0 s split (two halves of 491k unknowns, separator 1,400).
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "core/solver_status.hpp"
#include "core/types.hpp"

namespace c2d::core {

/// Runs body(h) for the halves h = 0, 1: side by side on two threads when `threads` > 1, else one
/// after the other on the calling thread, with OpenBLAS on one thread. Either way the OpenMP
/// regions a body opens (CHOLMOD's) run on the body's thread alone (ActiveLevelCap): the halves
/// are the parallelism, and one thread means one. False if a body returned false or ran out of
/// memory.
bool run_halves(int threads, const std::function<bool(int)>& body);

class SplitCholesky {
 public:
  SplitCholesky();
  ~SplitCholesky();
  SplitCholesky(const SplitCholesky&) = delete;
  SplitCholesky& operator=(const SplitCholesky&) = delete;

  /// Analyses, on `threads` threads (at most two are used), K's pattern (compressed; the lower triangle is read) for the split `part` (per
  /// unknown 0, 1 or 2 = separator) with each half and the separator eliminated in `order`
  /// (entry k: the unknown eliminated k-th). Unknowns of one half coupled to the other's
  /// (springs, contact penalties) join the separator. False, with nothing kept, when the split
  /// does not apply: sizes that do not match, a half left empty, or a separator too large for a
  /// dense Schur complement (more than kMaxSeparator unknowns or an eighth of K), or a
  /// CHOLMOD analysis that fails.
  bool analyse(const SpMat& k, const std::vector<int>& order,
               const std::vector<signed char>& part, int threads);
  /// Factorises K, of the pattern last analysed, on `threads` threads (at most two are used).
  /// kSingular when K is not positive definite.
  SolveStatus factorize(const SpMat& k, int threads);
  /// Solves K X = B with the last factorisation (no residual check).
  SolveStatus solve(const Eigen::MatrixXd& b, Eigen::MatrixXd& x, int threads);

  bool analysed() const;
  int separator_size() const;
  /// (min L_jj / max L_jj)² over the whole factor (the halves' own columns and the Schur
  /// complement's Cholesky factor), as cholmod_rcond for one factor.
  double pivot_ratio() const;
  /// Non-zeros of the two halves' factors and the Schur complement's.
  double factor_nonzeros() const;

  static constexpr int kMaxSeparator = 4000;

 private:
  struct Half;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace c2d::core
