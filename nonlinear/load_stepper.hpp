// The geometric-nonlinear analysis: load stepping with Newton (KINSOL) on the
// updated-Lagrangian St. Venant–Kirchhoff model, cutback and retry on a failed step.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "core/results.hpp"
#include "core/scene.hpp"
#include "nonlinear/newton_solver.hpp"

namespace c2d::nonlinear {

/// One attempt at one load step (a cut-back step leaves a failed record, then a retry).
struct StepRecord {
  int step = 0;              ///< converged steps so far, this one included when converged
  double load_factor = 0.0;  ///< the target λ of the attempt
  int attempt = 0;           ///< 0 first try, k after k cutbacks
  NewtonReport newton;
  double seconds = 0.0;
};

struct StepperOptions {
  int steps = 1;             ///< nominal number of equal load increments
  int max_cutbacks = 8;      ///< halvings of a failed increment before giving up
  NewtonOptions newton;
  /// Prescribed displacements at load factor λ (full vector; only constrained DOFs are read).
  /// Default: λ × the model's prescribed values.
  std::function<void(double lambda, VecX& u_full)> prescribe;
  /// Called after every attempt (progress display).
  std::function<void(const StepRecord&)> on_step;
};

/// Solves from λ = 0 to 1. On failure the results hold the last converged step, with the status
/// and message of the failure. Never throws on a numerical failure.
core::Results solve_geometric_nonlinear(const core::Model& model, const core::AnalysisSpec& analysis,
                                        const StepperOptions& options,
                                        std::vector<StepRecord>* trace = nullptr);

}  // namespace c2d::nonlinear
