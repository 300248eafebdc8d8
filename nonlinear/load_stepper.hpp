// The analysis driver: load stepping with Newton (KINSOL) on a structural system, the
// updated-Lagrangian St. Venant–Kirchhoff model or the small-strain one, cutback and retry on a
// failed step. Linear and geometric-nonlinear analyses, with or without contact, all pass here.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "constraints/contact_set.hpp"
#include "core/model.hpp"
#include "core/results.hpp"
#include "core/scene.hpp"
#include "nonlinear/contact_newton.hpp"
#include "nonlinear/newton_solver.hpp"

namespace c2d::nonlinear {

/// One attempt at one load step (a cut-back step leaves a failed record, then a retry).
struct StepRecord {
  int step = 0;              ///< converged steps so far, this one included when converged
  double load_factor = 0.0;  ///< the target λ of the attempt
  int attempt = 0;           ///< 0 first try, k after k cutbacks
  NewtonReport newton;       ///< every KINSOL iteration of the attempt
  /// Linear systems factorised in the attempt: the predictor's and Newton's Jacobians, with
  /// contact the method's solves too.
  int factorizations = 0;
  double seconds = 0.0;
  /// With contact: the outer (active-set) iterations of the attempt and, when it converged,
  /// the contact state per slave node (gap, force, pressure, active).
  std::vector<ContactIteration> contact;
  constraints::ContactReport contact_state;
  /// With contact: the method that finished the attempt (ConstraintStrategy::fallback), and
  /// why; empty: the scene's method throughout.
  std::string fallback, fallback_reason;
};

struct StepperOptions {
  int steps = 1;             ///< nominal number of equal load increments
  /// Halvings of the nominal increment: the smallest increment is nominal / 2^max_cutbacks,
  /// and a step that fails at it ends the run (with its Newton status).
  int max_cutbacks = 8;
  /// Attempts (converged and cut back) over the whole run before it ends `stalled`; 0: twice
  /// what the smallest increment needs to reach λ = 1, plus 100.
  int max_attempts = 0;
  NewtonOptions newton;
  /// Prescribed displacements at load factor λ (full vector; only constrained DOFs are read).
  /// Default: core::prescribed_displacement (λ × the supports' values; rotated supports turn
  /// through λθ).
  std::function<void(double lambda, VecX& u_full)> prescribe;
  /// Called after every attempt (progress display).
  std::function<void(const StepRecord&)> on_step;
  /// Called after every converged step with its fields (displacement, reactions, stresses,
  /// ZZ estimate, contact fields), e.g. to write one VTU per step. Costs a stress recovery.
  std::function<void(const StepRecord&, const core::Results&)> on_state;
};

/// The analysis driver: the load from λ = 0 to 1 in `options.steps` increments (cut back and
/// retried on failure) on the analysis' structural system: finite strain (updated Lagrangian,
/// K_T = K_D + K_σ) when `analysis.geometric_nonlinearity`, else small strain (K factorised once
/// for the run). A linear analysis is the small-strain system taking the load in one step, or,
/// when a load has an amplitude, in `options.steps` (its stages). On failure the results hold
/// the last converged step, with the status and message of the failure. Never throws on a
/// numerical failure; throws InputError (at the follower load) when a finite-strain model has
/// follower pressures and `contact` holds rows. With `contact`, every step runs the constrained
/// step (solve_contact_step); `contact_report` gets the state of the last converged step.
core::Results solve_load_steps(const core::Model& model, const core::AnalysisSpec& analysis,
                               const StepperOptions& options,
                               std::vector<StepRecord>* trace = nullptr,
                               const constraints::ContactSet* contact = nullptr,
                               constraints::ContactReport* contact_report = nullptr);

/// solve_load_steps with finite strain, whatever the analysis says.
core::Results solve_geometric_nonlinear(const core::Model& model, const core::AnalysisSpec& analysis,
                                        const StepperOptions& options,
                                        std::vector<StepRecord>* trace = nullptr,
                                        const constraints::ContactSet* contact = nullptr,
                                        constraints::ContactReport* contact_report = nullptr);

/// solve_load_steps with small strain, whatever the analysis says, in the analysis' steps
/// (default 1), its Newton limit, the default cutbacks.
core::Results solve_linear_static(const core::Model& model, const core::AnalysisSpec& analysis,
                                  const constraints::ContactSet* contact = nullptr,
                                  constraints::ContactReport* contact_report = nullptr);

}  // namespace c2d::nonlinear
