// The small-displacement analysis without contact: assemble K_ff, factorise, solve, recover
// reactions, stresses, smoothed stresses and the ZZ estimate. The solve in the middle can be
// replaced (the contact analysis hands K_ff and f to its constraint method).
#pragma once

#include <functional>

#include "core/model.hpp"
#include "core/results.hpp"
#include "core/scene.hpp"

namespace c2d::core {

/// Solves K_ff u_f = f_f − K_fc u_c: sets `r.status`, `r.message`, `r.solver` and u_free.
/// `u_prescribed` is the full vector with the supports' values (free entries 0).
using LinearSolve = std::function<void(const SpMat& k_ff, const VecX& rhs,
                                       const VecX& u_prescribed, VecX& u_free, Results& r)>;

/// Assembles K_ff and f_f − K_fc u_c, solves them with `solve` (default: CHOLMOD, or Eigen's
/// LDLᵀ when analysis.solver is "ldlt"), then recovers the fields. A solve that stopped at an
/// iteration limit or on a cycle (kMaxIterations, kCycling) still has its displacement
/// recovered; any other failure leaves zero fields. Never throws on a numerical failure.
Results solve_linear(const Model& model, const AnalysisSpec& analysis,
                     const LinearSolve& solve = {});

}  // namespace c2d::core
