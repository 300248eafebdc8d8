// The small-displacement analysis: one load step, K_σ = 0. The load stepper of the geometric
// nonlinear analysis reduces to this path for a linear scene.
#pragma once

#include "constraints/contact_set.hpp"
#include "core/model.hpp"
#include "core/results.hpp"
#include "core/scene.hpp"

namespace c2d::nonlinear {

/// Assembles K_ff and solves K_ff u_f = f_f - K_fc u_c with CHOLMOD, or, with contact, hands
/// K_ff, f and the gap rows to the contact strategy; then recovers reactions, stresses,
/// smoothed stresses and the ZZ estimate. With contact, detection is repeated at the deformed
/// configuration until no slave node changes its master (a node sliding to the next edge), at
/// most 5 passes. Never throws on a numerical failure: the status says.
core::Results solve_linear_static(const core::Model& model, const core::AnalysisSpec& analysis,
                                  const constraints::ContactSet* contact = nullptr,
                                  constraints::ContactReport* contact_report = nullptr);

}  // namespace c2d::nonlinear
