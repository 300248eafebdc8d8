// The small-displacement analysis: one load step, K_σ = 0. The load stepper of the geometric
// nonlinear analysis reduces to this path for a linear scene.
#pragma once

#include "core/model.hpp"
#include "core/results.hpp"
#include "core/scene.hpp"

namespace c2d::nonlinear {

/// Assembles K_ff, solves K_ff u_f = f_f - K_fc u_c with CHOLMOD, recovers reactions, stresses,
/// smoothed stresses and the ZZ estimate. Never throws on a numerical failure: the status says.
core::Results solve_linear_static(const core::Model& model, const core::AnalysisSpec& analysis);

}  // namespace c2d::nonlinear
