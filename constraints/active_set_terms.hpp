// What a constraint method adds to a Newton solve once its active set is held fixed.
//
// The caller owns the structural equations R_s(u) = f_int(u) − λ f and their tangent K_T; the
// gap rows are g(u) with gradient G (linear over the solve in small strain, re-evaluated at every
// iterate in finite strain, where the caller adds the contact's geometric stiffness to K_T).
// A method's terms add
//   penalty-type:    the forces λ̂ − k g_A(u) of the active rows, and G_Aᵀ diag(k) G_A to K_T
//                    (no further unknowns; CHOLMOD);
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
  /// Unknowns beyond u: 0 for penalty-type terms, one per row for multiplier-type terms.
  virtual int extra_unknowns() const = 0;
  /// The extra unknowns that reproduce the row forces `force` (ignored by penalty-type terms).
  virtual void pack_forces(const VecX& force, Eigen::Ref<VecX> extra) const = 0;
  /// Row forces λ ≥ 0 (compressive) at gaps `gap` and extra unknowns `extra`.
  virtual VecX forces(const VecX& gap, const Eigen::Ref<const VecX>& extra) const = 0;
  /// The extra equations' residual at `gap` and `extra` (nothing for penalty-type terms).
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

/// Penalty-type terms: rows with `active` set carry λ̂_i − k_i g_i(u).
std::unique_ptr<ActiveSetTerms> make_penalty_terms(const SpMat& g, const std::vector<char>& active,
                                                   const VecX& k, const VecX& lambda_hat);

/// Multiplier-type terms with row scale `s`: the rows with `active` set hold g_i(u) = 0 through
/// their multipliers; without active rows the Newton matrix is K_T alone (CHOLMOD).
std::unique_ptr<ActiveSetTerms> make_multiplier_terms(const SpMat& g,
                                                      const std::vector<char>& active, double s);

}  // namespace c2d::constraints
