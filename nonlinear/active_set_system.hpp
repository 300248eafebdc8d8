// The nonlinear equations of one outer iteration of the constrained step (contact_newton.hpp):
// the active set fixed by slot, and the strategy's terms for that set (its forces and
// stiffness, or its multipliers):
//   R(x) = [ f_int(u) − λ f − G(u)ᵀ λ(x) ;  r_terms(x) ],   x = [u; the terms' unknowns].
// Small strain: the rows are linear, g(u) = c + G u (the linearisation about the detection
// state). Finite strain: the rows are detected again at every iterate, each slot keeping its
// place, with their exact gradients, and the Jacobian carries the contact's geometric
// stiffness −Σ λ_i ∂²g_i: gaps, normals and projections follow the iterate, so Newton
// converges quadratically while contacts slide and the outer iterations change active sets
// only. The equality rows ([[constraint]], [[plate]]) follow the gap rows, always held; a
// plate's rows turn with it in finite strain, evaluated at every iterate with their curvature.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "constraints/active_set_terms.hpp"
#include "constraints/contact_set.hpp"
#include "nonlinear/newton_solver.hpp"
#include "nonlinear/structural_system.hpp"

namespace c2d::nonlinear {

class ActiveSetSystem final : public NewtonSystem {
 public:
  /// `rows`: the gap rows detected for the outer iteration (their slots and order); `g`, `c`:
  /// those rows linearised at the detection state (g(u) = c + G u), then the equality rows
  /// A u + c_eq = 0; `active`: the gap rows' set followed by the equality rows.
  /// `linear_tail` rows at the end (after the equality rows) stay linear in every
  /// configuration: friction's sticking rows.
  ActiveSetSystem(StructuralSystem& base, const constraints::ContactSet& contact,
                  const std::vector<constraints::GapRow>& rows, const SpMat& g, const VecX& c,
                  std::unique_ptr<constraints::ActiveSetTerms> terms,
                  const std::vector<char>& active, int linear_tail = 0);

  int num_gaps() const { return static_cast<int>(template_.size()); }
  int size() const { return n_ + terms_->extra_unknowns(); }
  /// x = [u; the terms' unknowns reproducing the row forces `force`].
  VecX pack(const VecX& u, const VecX& force) const;
  /// The held rows' gaps at x (false: an active row found no master there).
  bool gap(const VecX& x, VecX& g);
  /// The gap rows at x: the detection's in small strain, re-detected in finite strain.
  const std::vector<constraints::GapRow>& rows() const { return moving_ ? rows_now_ : template_; }
  /// Row forces at x (gap rows: λ ≥ 0 compressive; then the equality rows' multipliers).
  VecX forces(const VecX& x, const VecX& gap) const;
  double row_stiffness() const { return terms_->row_stiffness(); }
  /// A force on the free DOFs held fixed through the solve (the friction forces −Tᵀλ_t the
  /// method found: friction is resolved by the method at each outer iteration, not by Newton).
  void set_fixed_force(const VecX& f) { fixed_force_ = f; }
  /// Bounds in magnitude the row forces that weigh the rows' curvature in the Jacobian (gap
  /// rows, then equality rows). A penalty row's force k·g(x) at an iterate far from the
  /// solution can exceed every force the method found by orders (the method's step linearised
  /// its gap along a master segment it then left); its curvature term then swamps K_T and
  /// throws Newton's step off by far more than the error it corrects. Near a solution a force
  /// exceeds the method's by the step's error at most, and so does the tangent's.
  void bound_curvature_forces(const VecX& bound) { curvature_bound_ = bound; }

  bool residual(const VecX& x, VecX& r) override;
  bool factorize_jacobian(const VecX& x) override;
  bool solve(const VecX& b, VecX& x) override { return terms_->solve(b, x); }
  std::string evaluation_failure() const override;

 private:
  /// Finite strain: the rows, G and the gaps at x (kept for the last x evaluated). A slot
  /// found no longer keeps its last row when it is open (it carries no force); an active one
  /// fails the evaluation.
  /// With `curvature`, the rows' Hessians too (the Jacobian's geometric stiffness); a residual
  /// needs values and gradients only, a ninth of the cost.
  bool evaluate(const VecX& x, bool curvature = false);

  StructuralSystem& base_;
  const constraints::ContactSet& contact_;
  bool moving_;
  std::vector<constraints::GapRow> template_;
  std::vector<char> active_;
  SpMat g_, gt_;      ///< G at the last iterate (finite strain) or the detection's
  SpMat g_template_;  ///< the detection's G: with c, the open rows' linear gaps
  VecX c_;
  std::unique_ptr<constraints::ActiveSetTerms> terms_;
  int n_;
  int linear_tail_ = 0;
  VecX fixed_force_;
  VecX curvature_bound_;  ///< per held row: the largest force its curvature term is weighed with
  // Finite strain: the rows at the last iterate evaluated.
  bool evaluated_ = false;
  bool curved_ = false;  ///< the rows evaluated carry their curvature
  VecX at_, gap_now_;
  std::vector<constraints::GapRow> rows_now_;
  std::vector<constraints::EqualityRow> eq_now_;  ///< nonlinear equality rows at the iterate
  SpMat jacobian_;
  std::string lost_;
};

}  // namespace c2d::nonlinear
