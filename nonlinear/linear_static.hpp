// The small-displacement analysis: one load step, K_σ = 0, through the same constrained step
// as the load-stepped analysis when the scene has contact.
#pragma once

#include "constraints/contact_set.hpp"
#include "core/model.hpp"
#include "core/results.hpp"
#include "core/scene.hpp"

namespace c2d::nonlinear {

/// core::solve_linear; with contact, its solve is the constrained step of the load-stepped
/// analysis (solve_contact_step) taken once on the small-strain system: detect, solve with the
/// scene's method, hold the set, re-detect at the deformed configuration until the rows and
/// gaps reproduce the state, at most 15 outer iterations (a cap reached is status
/// max_iterations, not converged). Never throws on a numerical failure: the status says.
core::Results solve_linear_static(const core::Model& model, const core::AnalysisSpec& analysis,
                                  const constraints::ContactSet* contact = nullptr,
                                  constraints::ContactReport* contact_report = nullptr);

}  // namespace c2d::nonlinear
