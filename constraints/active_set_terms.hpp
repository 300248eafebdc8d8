// What a constraint method adds to a Newton solve once its active set is held fixed.
//
// The caller owns the structural equations R_s(u) = f_int(u) − λ f and their tangent K_T; the
// gap rows are g(u) with gradient G (linear over the solve in small strain, re-evaluated at every
// iterate in finite strain, where the caller adds the contact's geometric stiffness to K_T).
// A method's terms add
//   penalty-type:    the active rows' forces z = λ/s as unknowns, with the penalty law
//                    g_A(u) + (λ − λ̂)/k = 0 (weighed by s) and z_I = 0; solved by eliminating
//                    z, on K_T + G_Aᵀ diag(k) G_A (CHOLMOD); or the law's forces λ̂ − k g_A(u)
//                    with no further unknowns (the augmented Lagrangian's);
//   multiplier-type: the active rows' multipliers z = λ/s as unknowns, with g_A(u) = 0 and
//                    z_I = 0 (the saddle point, through SaddlePointSolver).
// The unknown vector is x = [u; extra]; the residual is [R_s(u) − Gᵀ λ(x); r_extra(x)].
#pragma once

#include <memory>
#include <vector>

#include "core/types.hpp"

namespace c2d::constraints {

class ActiveSetTerms {
 public:
  virtual ~ActiveSetTerms() = default;
  /// Unknowns beyond u: one per row, or none for the primal penalty terms.
  virtual int extra_unknowns() const = 0;
  /// The extra unknowns that reproduce the row forces `force` (none: ignored).
  virtual void pack_forces(const VecX& force, Eigen::Ref<VecX> extra) const = 0;
  /// Row forces λ ≥ 0 (compressive) at gaps `gap` and extra unknowns `extra`.
  virtual VecX forces(const VecX& gap, const Eigen::Ref<const VecX>& extra) const = 0;
  /// The extra equations' residual at `gap` and `extra` (none: nothing).
  virtual void extra_residual(const VecX& gap, const Eigen::Ref<const VecX>& extra,
                              Eigen::Ref<VecX> r) const = 0;
  /// Replaces the rows' gradient G (same rows, same order): finite strain re-evaluates the
  /// rows at every Newton iterate.
  virtual void update_rows(const SpMat& g) = 0;
  /// Factorises the Newton matrix built on the structural tangent `k_t` (kept by reference
  /// until the next call; its pattern may change between calls); false when it is singular.
  virtual bool factorize(const SpMat& k_t) = 0;
  /// Solves the last factorised Newton matrix; false on failure.
  virtual bool solve(const VecX& b, VecX& x) = 0;
  /// The largest stiffness the terms give one row (a penalty k or the multiplier scale s), for
  /// the round-off floor of the residual.
  virtual double row_stiffness() const = 0;
};

/// Penalty-type terms: rows with `active` set carry λ_i = λ̂_i − k_i g_i(u). With
/// `forces_unknown` the forces are unknowns (scale `s`) and the law their equation, measured as
/// an exact method's rows are; without, the forces follow from u.
std::unique_ptr<ActiveSetTerms> make_penalty_terms(const SpMat& g, const std::vector<char>& active,
                                                   const VecX& k, const VecX& lambda_hat,
                                                   double s, bool forces_unknown);

/// Multiplier-type terms with row scale `s`: the rows with `active` set hold g_i(u) = 0 through
/// their multipliers; without active rows the Newton matrix is K_T alone (CHOLMOD).
std::unique_ptr<ActiveSetTerms> make_multiplier_terms(const SpMat& g,
                                                      const std::vector<char>& active, double s);

}  // namespace c2d::constraints
