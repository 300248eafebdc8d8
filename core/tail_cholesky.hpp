// Sparse Cholesky factor with a chosen set of unknowns, the tail, ordered last:
//
//   P K Pᵀ = L D Lᵀ,   L = [ L₁₁  0  ]     the tail's k unknowns are the last k of P,
//                          [ L₂₁ L₂₂ ]     so L₂₂ D₂ L₂₂ᵀ = K_TT − K_TI K_II⁻¹ K_IT.
//
// D = I for CHOLMOD's supernodal factor (L Lᵀ); its simplicial factor (small matrices) is
// L D Lᵀ with unit L, which also factorises a symmetric indefinite K with nonzero pivots, as
// SpdSolver's does: the same matrices factorise on either path.
//
// The ordering is CHOLMOD's CAMD (minimum degree under the constraint "tail last"), on K or on
// a given fill order's mesh graph (set_ordering, FillOrder::tail_last); L₂₂ is the
// Cholesky factor of the tail's Schur complement, i.e. the stiffness condensed onto the tail.
// A right-hand side that lives on the tail (a constraint row's Cᵀ when the tail holds every
// unknown the constraints touch) then costs dense O(k²) work on L₂₂ instead of two sparse
// triangular solves over all n unknowns: forward substitution of such a vector never leaves
// the tail, and the tail's part of K⁻¹ b needs only L₂₂ᵀ. This is static condensation onto the
// contact surface, taken from the factorisation's own ordering rather than a second matrix.
#pragma once

#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "core/fill_ordering.hpp"
#include "core/spd_solver.hpp"

namespace c2d::core {

/// Symbolic analyses that outlive one TailCholesky. Every Newton iteration of a load step
/// condenses K_T anew, with K_T's pattern and, once the contact has settled, the tail
/// unchanged: the analysis (the order with the tail last, the elimination tree, the supernodes)
/// is then the same one, and on Cattaneo–Mindlin it cost a fifth of each factorisation. A
/// TailCholesky given these (set_analyses) takes a copy of a matching analysis instead of
/// analysing again (K's pattern compared in full, the tail, its parts and the fill order), and
/// offers each analysis it makes. Keeps the last few; safe to share between threads.
class TailAnalyses {
 public:
  TailAnalyses();
  ~TailAnalyses();
  TailAnalyses(const TailAnalyses&) = delete;
  TailAnalyses& operator=(const TailAnalyses&) = delete;

 private:
  friend class TailCholesky;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class TailCholesky {
 public:
  TailCholesky();
  ~TailCholesky();
  TailCholesky(const TailCholesky&) = delete;
  TailCholesky& operator=(const TailCholesky&) = delete;

  /// Factorises K (symmetric; the lower triangle is used) with the unknowns `tail` ordered
  /// last. The ordering and symbolic analysis are kept while K's pattern (compared in full),
  /// the tail and its parts are unchanged, or taken from the shared analyses (set_analyses).
  /// Reports kSingular when K is not positive definite.
  /// `tail_part` (empty, or a part number per entry of `tail`) groups the tail by part, lowest
  /// first, each part in the order the ordering gives it: L₂₂ is then block diagonal when no
  /// entry of K joins two parts.
  SolveStatus factorize(const SpMat& k, const std::vector<int>& tail,
                        const std::vector<int>& tail_part = {});
  /// Orders matrices of its size by one of `fill`'s tail-last orders instead of CAMD on the
  /// matrix: CAMD on the corner graph of mesh_fill_order's mesh (FillOrder::tail_last) or the
  /// order with the tail moved last (moved_last), whichever factor takes fewer flops; the
  /// report's `ordering` says which ("corner_camd", "given_tail_last").
  void set_ordering(std::shared_ptr<const FillOrder> fill);
  /// Takes matching symbolic analyses from `analyses` and offers it its own (null: none).
  void set_analyses(std::shared_ptr<TailAnalyses> analyses);

  int size() const { return n_; }
  /// k, the tail's size.
  int tail_size() const { return static_cast<int>(tail_factor_.rows()); }
  /// Per unknown: its row in L₂₂, or −1 outside the tail.
  const std::vector<int>& tail_position() const { return tail_position_; }
  /// L₂₂, dense, lower triangle meaningful (unit diagonal for an L D Lᵀ factor).
  const Eigen::MatrixXd& tail_factor() const { return tail_factor_; }
  /// D₂, the tail's pivots (ones for an L Lᵀ factor).
  const VecX& tail_pivots() const { return tail_pivots_; }

  /// w = (L D)⁻¹ P b, in the factor's order: the tail is w's last k entries.
  SolveStatus forward(const VecX& b, VecX& w);
  /// x = Pᵀ L⁻ᵀ w, so that x = K⁻¹ b for w = forward(b).
  SolveStatus backward(const VecX& w, VecX& x);

  /// Status, pivot ratio, factor size and the seconds of each phase (summed).
  const SpdSolveReport& report() const { return report_; }

 private:
  struct Impl;
  bool analyse(const SpMat& k, const std::vector<int>& tail);
  /// Groups the tail (the last entries of `perm`) by its parts, if any.
  void group_tail(const std::vector<int>& tail, std::vector<int>& perm) const;
  /// A copy of a matching analysis from the shared analyses, if one is kept.
  bool adopt(const SpMat& k, const std::vector<int>& tail);
  /// Each tail unknown's row in L₂₂, from the analysed order; false if the tail is not last.
  bool place_tail(const std::vector<int>& tail);
  bool extract_tail_factor();
  SolveStatus fail(SolveStatus status, const std::string& message);
  /// out = second(first(in)) for two CHOLMOD solve systems (CHOLMOD_P, _LD, _Lt, _Pt).
  SolveStatus apply_pair(int first, int second, const VecX& in, VecX& out, const char* what);
  std::unique_ptr<Impl> impl_;
  int n_ = 0;
  std::vector<int> tail_position_;
  Eigen::MatrixXd tail_factor_;
  VecX tail_pivots_;
  SpdSolveReport report_;
};

}  // namespace c2d::core
