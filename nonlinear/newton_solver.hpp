// Newton's method through SUNDIALS KINSOL, with the Newton systems handed to our sparse
// factorisation (a custom SUNMatrix / SUNLinearSolver pair: the system assembles K_T into its own
// Eigen matrix and factorises it with CHOLMOD, symbolic analysis reused).
#pragma once

#include <string>
#include <vector>

#include "core/solver_status.hpp"
#include "core/types.hpp"

namespace c2d::nonlinear {

/// What Newton needs from a discrete problem R(u) = 0.
class NewtonSystem {
 public:
  virtual ~NewtonSystem() = default;
  /// R(u). Returns false when R cannot be evaluated at u (an inverted element): KINSOL's line
  /// search then tries a shorter step.
  virtual bool residual(const VecX& u, VecX& r) = 0;
  /// Assembles and factorises the Jacobian at u; false when the factorisation fails.
  virtual bool factorize_jacobian(const VecX& u) = 0;
  /// Solves J x = b with the last factorisation.
  virtual bool solve(const VecX& b, VecX& x) = 0;
  /// Why the last residual or Jacobian could not be evaluated, in words ("" when it could or
  /// the system does not know), e.g. the first inverted element.
  virtual std::string evaluation_failure() const { return ""; }
};

struct NewtonOptions {
  double residual_tolerance = 1e-8;  ///< ‖R‖_∞ ≤ tol × residual_scale
  double residual_scale = 1.0;       ///< e.g. the load's ‖f_ext‖_∞
  int max_iterations = 25;
  bool line_search = true;
};

struct NewtonReport {
  SolveStatus status = SolveStatus::kFailed;
  std::string message;
  int iterations = 0;
  int factorizations = 0;              ///< Jacobians factorised (one per Newton iteration)
  /// Of `iterations`, the contact method's steps that Newton with the set held continued from
  /// (each a linearised solve with the sets updated, the first iteration of that Newton).
  int method_steps = 0;
  std::vector<double> residual_norms;  ///< ‖R‖_∞ at each Jacobian evaluation, then the final one
  double final_residual = 0.0;         ///< ‖R‖_∞ at the returned u
  double last_step = 0.0;              ///< scaled length of the last Newton step
};

/// Solves R(u) = 0 from the initial guess u (overwritten with the result).
NewtonReport solve_newton(NewtonSystem& system, VecX& u, const NewtonOptions& options);

/// Full Newton steps first, then (if that fails and options.line_search is set) a second
/// attempt from the same guess with KINSOL's line search. On slender structures the residual may
/// rise for one iteration before it collapses, which a line search mistakes for divergence. The
/// report combines both attempts' iterations and norms.
NewtonReport solve_newton_with_fallback(NewtonSystem& system, VecX& u, const NewtonOptions& options);

}  // namespace c2d::nonlinear
