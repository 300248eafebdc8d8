// One interface for every way of enforcing constraints: one class per method, registered in
// constraints/method_registry.cpp. A method solves the linearised problem (its active-set
// update) and gives the terms with which a Newton solve holds that set.
#pragma once

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "constraints/active_set_terms.hpp"
#include "constraints/constrained_problem.hpp"
#include "constraints/row_memory.hpp"
#include "constraints/set_rules.hpp"

namespace c2d::constraints {

/// Options shared by the backends; each uses the ones that concern it. Validated by
/// `validate()` before a strategy is created.
struct StrategyOptions {
  std::string method = "lagrange";  ///< a name of the method registry
  /// penalty: an absolute stiffness (> 0) or, when 0, `penalty_factor` × the local stiffness.
  double penalty_k = 0.0;
  double penalty_factor = 1.0e3;
  /// Penetration tolerance: absolute when > 0, else relative × the smallest contact edge.
  double tolerance = 0.0;
  double relative_tolerance = 1.0e-6;
  /// The physical limit a final state's measured penetration is held against, × the shortest
  /// contact edge: a regularised method converges to its own penetration, which may be no
  /// answer to the contact problem (k = 10 let a block sink 91 % into its support); beyond the
  /// limit the run keeps its status and says so in summary.json's warnings and on the terminal.
  double penetration_limit = 0.02;
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

/// What a method carries from one accepted load step to the next, per row slot (a row's
/// identity across detections, ContactPairs::num_slots): its state (0 open, 1 closed and
/// sticking, 2 closed and slipping along +t, 3 along −t), with friction the friction force λ_t
/// it held, and the normal force λ_n (each empty: none yet); and how far the step's contact
/// grew: the largest gap, at its linearisation point, of a row that closed in one of the
/// step's solves (0: none closed).
struct StepHistory {
  std::vector<char> states;
  VecX tangent_force;
  VecX normal_force;
  double closing_reach = 0.0;
};

class ConstraintStrategy {
 public:
  /// `options.method` is the registered name the strategy reports.
  explicit ConstraintStrategy(const StrategyOptions& options) : options_(options) {}
  virtual ~ConstraintStrategy() = default;
  const std::string& name() const { return options_.method; }
  /// Enforces the constraints exactly (up to round-off), or up to a regularisation.
  virtual bool exact() const = 0;
  /// How a state that Newton reached with the set held is recognised as the method's solution,
  /// so that it ends a load step without a solve that would only confirm it: the rule that must
  /// keep the state's set (from its forces, gaps and slips alone), and the penetration the state
  /// may have. No rule: no state alone can tell.
  struct StateTest {
    const SetRule* rule = nullptr;
    double max_penetration = std::numeric_limits<double>::infinity();
  };
  /// The exact methods: their own rule (their multipliers are the state's forces). Overridden by
  /// the pure penalty (its own rule without friction) and auglag (the primal-dual rule);
  /// adaptive_penalty has none (it may raise k at that state).
  virtual StateTest state_test(const ConstrainedProblem&) const {
    return exact() ? StateTest{&set_rule()} : StateTest{};
  }
  /// Solves the problem, from what `memory` carries for its rows (nothing: a cold start).
  /// Never throws for numerical trouble: the status and message say what happened, and every
  /// field is finite. Times the method, names it in the solution and derives the gaps,
  /// penetration and equality violation from u.
  ConstraintSolution solve(const ConstrainedProblem& problem, const RowMemory& memory = {});
  /// The terms a Newton solve adds to hold the active set of `solution` (which this strategy
  /// returned for `problem`) fixed: the method's forces and stiffness, or its multipliers.
  /// Their rows are the gap rows followed by the equality rows, which are always held.
  virtual std::unique_ptr<ActiveSetTerms> active_set_terms(
      const ConstrainedProblem& problem, const ConstraintSolution& solution) const = 0;
  /// The rule by which the method's set iterations choose each row's next normal and
  /// tangential state (set_rules.hpp): the one set engine asks it, for every method.
  virtual const SetRule& set_rule() const = 0;
  /// The history of the last accepted load step, where every attempt at the next one starts.
  const StepHistory& history() const { return accepted_; }
  /// Hooks of a load-stepped analysis: the step just solved was accepted with `converged` as
  /// its history, which becomes the method's snapshot; or it is being cut back, and the next
  /// attempt starts again from the snapshot (a method with more state per step restores it in
  /// on_step_rejected).
  void step_accepted(StepHistory converged);
  void step_rejected();
  /// The method that finishes a load step whose outer iterations cycle (their sets return to
  /// an earlier combination) or whose problem this method cannot pose
  /// (ConstraintSolution::not_applicable), or null: the step then ends `cycling`, or with the
  /// method's failure. Only a method with the same solution may serve.
  virtual std::unique_ptr<ConstraintStrategy> fallback() const { return nullptr; }

  /// The only place a method name becomes a class (through the method registry). Throws
  /// InputError for an unknown method or invalid options.
  static std::unique_ptr<ConstraintStrategy> create(const StrategyOptions& options);

 protected:
  /// The method itself: u, forces, multipliers, active set, status, history.
  virtual ConstraintSolution solve_problem(const ConstrainedProblem& problem,
                                           const RowMemory& memory) = 0;

  /// A method's own per-step state beyond StepHistory: kept or restored here. Nothing by default.
  virtual void on_step_accepted() {}
  virtual void on_step_rejected() {}

  StrategyOptions options_;

 private:
  StepHistory accepted_;
};

/// A method that enforces the constraints up to a regularisation (a penalty stiffness per
/// row): a Newton solve holds its active set with the forces λ̂ − k g it reports.
class RegularisedStrategy : public ConstraintStrategy {
 public:
  using ConstraintStrategy::ConstraintStrategy;
  bool exact() const final { return false; }
  std::unique_ptr<ActiveSetTerms> active_set_terms(const ConstrainedProblem& problem,
                                                   const ConstraintSolution& s) const final;
  /// The return map of the regularised rows.
  const SetRule& set_rule() const final { return rule_; }

 protected:
  /// Whether λ̂ is the method's multiplier estimate, which each of its solves fixes anew (the
  /// augmented Lagrangian): Newton with its set held then takes the law's forces at u, not
  /// forces of its own (make_penalty_terms).
  virtual bool augmented() const { return false; }

 private:
  ReturnMapRule rule_;
};

/// A method that enforces the constraints exactly through multipliers: a Newton solve holds
/// its active set with the saddle point of the active rows.
class ExactStrategy : public ConstraintStrategy {
 public:
  using ConstraintStrategy::ConstraintStrategy;
  bool exact() const final { return true; }
  std::unique_ptr<ActiveSetTerms> active_set_terms(const ConstrainedProblem& problem,
                                                   const ConstraintSolution& s) const final;
};

}  // namespace c2d::constraints
