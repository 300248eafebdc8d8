// One interface for every way of enforcing constraints; one class per method; one factory.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "constraints/constrained_problem.hpp"

namespace c2d::constraints {

/// Options shared by the backends; each uses the ones that concern it. Validated by
/// `validate()` before a strategy is created.
struct StrategyOptions {
  std::string method = "lagrange";  ///< one of method_names()
  /// penalty: an absolute stiffness (> 0) or, when 0, `penalty_factor` × the local stiffness.
  double penalty_k = 0.0;
  double penalty_factor = 1.0e3;
  /// Penetration tolerance: absolute when > 0, else relative × the smallest contact edge.
  double tolerance = 0.0;
  double relative_tolerance = 1.0e-6;
  /// adaptive_penalty: factor applied to a row's k while it penetrates too much, and the cap
  /// on k relative to the local stiffness.
  double penalty_growth = 10.0;
  double max_penalty_factor = 1.0e8;
  /// auglag: augmentation stiffness relative to the local stiffness.
  double augmentation_factor = 10.0;
  /// ipopt: convergence tolerance on the scaled KKT error.
  double ipopt_tolerance = 1.0e-10;
  int max_iterations = 50;

  /// Empty when valid, else a sentence naming the offending option.
  std::string validate() const;
};

/// All method names, in the order reports list them.
const std::vector<std::string>& method_names();
/// Methods that enforce the constraints exactly (up to round-off).
bool is_exact_method(const std::string& method);

class ConstraintStrategy {
 public:
  virtual ~ConstraintStrategy() = default;
  virtual std::string name() const = 0;
  /// Solves the problem. Never throws for numerical trouble: the status and message say what
  /// happened, and every field is finite. Times the method, names it in the solution and
  /// derives the gaps, penetration and equality violation from u.
  ConstraintSolution solve(const ConstrainedProblem& problem);

  /// The only place a method name becomes a class. Throws InputError for an unknown method or
  /// invalid options.
  static std::unique_ptr<ConstraintStrategy> create(const StrategyOptions& options);

 protected:
  /// The method itself: u, forces, multipliers, active set, status, history.
  virtual ConstraintSolution solve_problem(const ConstrainedProblem& problem) = 0;
};

}  // namespace c2d::constraints
