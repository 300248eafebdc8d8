#include "constraints/methods/penalty_strategy.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

#include "constraints/friction_solver.hpp"
#include "constraints/penalized_solver.hpp"

namespace c2d::constraints {

void default_penalties(const ConstrainedProblem& p, const RowMemory& memory, double absolute_k,
                       double factor, VecX& k_gap, VecX& k_eq) {
  const VecX local_gap = p.gap_local_stiffness(memory);
  const VecX local_eq = p.row_stiffness(p.eq_jacobian);
  auto pick = [&](const VecX& local, int i) {
    return absolute_k > 0 ? absolute_k : factor * (local[i] > 0 ? local[i] : 1.0);
  };
  k_gap.resize(p.num_gaps());
  for (int i = 0; i < p.num_gaps(); ++i)
    k_gap[i] = p.gap_penalty.size() == p.num_gaps() && p.gap_penalty[i] > 0 ? p.gap_penalty[i]
                                                                            : pick(local_gap, i);
  k_eq.resize(p.num_equalities());
  for (int j = 0; j < p.num_equalities(); ++j) k_eq[j] = pick(local_eq, j);
}

FrictionalOptions penalised_friction(const SetRule& rule, const ConstrainedProblem& p,
                                     const RowMemory& memory, const VecX& k_gap, const VecX& lambda,
                                     const VecX& k_eq, const VecX& mu) {
  FrictionalOptions o;
  o.rule = &rule;
  o.k_gap = k_gap;
  o.k_tangent = tangent_penalties(p, k_gap);
  o.k_eq = k_eq;
  o.lambda_hat = lambda;
  o.mu_hat = mu;
  // The return map's tangential spring starts from the force of the last converged state.
  o.tangent_hat = memory.tangent_force0.size() == p.num_gaps() ? memory.tangent_force0
                                                               : VecX(VecX::Zero(p.num_gaps()));
  return o;
}

namespace {
/// The largest share of a force its round-off may take before the penalty is reported
/// ill-conditioned: three significant digits.
constexpr double kForceDigits = 1e-3;

// Largest ratio of a row's penalty to its local stiffness: how many digits the penalty costs.
// Rows whose local stiffness is not positive (a tangent that lost definiteness around a
// collapsing element) have no such measure and are left out: their trouble is not the penalty.
double penalty_ratio(const ConstrainedProblem& p, const RowMemory& memory, const VecX& k_gap,
                     const VecX& k_eq) {
  double r = 0.0;
  const VecX lg = p.gap_local_stiffness(memory), le = p.row_stiffness(p.eq_jacobian);
  for (int i = 0; i < k_gap.size(); ++i)
    if (lg[i] > 0) r = std::max(r, k_gap[i] / lg[i]);
  for (int j = 0; j < k_eq.size(); ++j)
    if (le[j] > 0) r = std::max(r, k_eq[j] / le[j]);
  return r;
}
}  // namespace

ConstraintSolution PenaltyStrategy::solve_problem(const ConstrainedProblem& p,
                                                  const RowMemory& memory) {
  ConstraintSolution s;
  VecX k_gap, k_eq;
  default_penalties(p, memory, options_.penalty_k, options_.penalty_factor, k_gap, k_eq);
  const VecX zero_gap = VecX::Zero(p.num_gaps()), zero_eq = VecX::Zero(p.num_equalities());
  bool assembled = true;  // whether the solve factorised K + Gᵀ k G itself
  PenalizedSolver solver(p, set_rule());
  if (p.has_friction()) {
    FrictionalOptions o = penalised_friction(set_rule(), p, memory, k_gap, zero_gap, k_eq, zero_eq);
    o.max_iterations = options_.max_iterations;
    solve_frictional(p, memory, o, s);
  } else {
    std::vector<char> active = initially_closed(p, memory);
    const auto outcome = solver.solve(k_gap, zero_gap, k_eq, zero_eq, options_.max_iterations,
                                      active, s.u, s.history, 1);
    s.status = outcome.status;
    s.message = outcome.message;
    solver.report_counts(s);
    assembled = !solver.condensed();
  }
  const bool solved = s.status == SolveStatus::kConverged ||
                      s.status == SolveStatus::kCycling || s.status == SolveStatus::kMaxIterations;
  if (p.has_friction())
    s.eq_penalty = k_eq;  // the frictional solve reports the forces of its sets
  else if (solved)
    solver.forces(k_gap, zero_gap, k_eq, zero_eq, s);
  // A penalty many orders above the element stiffness: say so instead of returning what it
  // produced when its digits are gone. Assembled, K + Gᵀ k G's factor keeps none (its pivot
  // ratio). Condensed, the factor keeps its digits, but the forces k·g that the run's Newton
  // and report take from the gaps carry the gaps' round-off times k: measured as their
  // distance from the condensed solve's own forces.
  const double ratio = penalty_ratio(p, memory, k_gap, k_eq);
  if (ratio > 1e6) {
    double force = 0.0;
    if (solved) {
      if (s.contact_force.size()) force = s.contact_force.cwiseAbs().maxCoeff();
      if (s.eq_multiplier.size()) force = std::max(force, s.eq_multiplier.cwiseAbs().maxCoeff());
    }
    const double round_off =
        solved && !p.has_friction() ? solver.force_round_off(k_gap, zero_gap, k_eq, zero_eq, s.u)
                                    : 0.0;
    const bool factor_lost =
        assembled && (s.status == SolveStatus::kSingular || s.pivot_ratio < 1e-12);
    const double unresolved =
        solved && !p.has_friction() ? solver.unresolved_penetration(s.contact_force, k_gap, s.u)
                                    : 0.0;
    const bool forces_lost =
        force > 0 && (round_off > kForceDigits * force || unresolved > 1.0);
    if (factor_lost || forces_lost) {
      char buf[320];
      if (factor_lost)
        std::snprintf(buf, sizeof buf,
                      "penalty k is %.3g x the local element stiffness; the factor's pivot ratio "
                      "%.3g leaves no significant digits (lower k or use an exact method)",
                      ratio, s.pivot_ratio);
      else if (unresolved > 1.0)
        std::snprintf(buf, sizeof buf,
                      "penalty k is %.3g x the local element stiffness; the penetration it leaves "
                      "is %.3g times below the gaps' round-off, so its contact set reads noise "
                      "(lower k or use an exact method)",
                      ratio, unresolved);
      else
        std::snprintf(buf, sizeof buf,
                      "penalty k is %.3g x the local element stiffness; its forces k*g stand %.3g "
                      "from the solve's own (the gaps' round-off times k) against the largest "
                      "force %.3g (lower k or use an exact method)",
                      ratio, round_off, force);
      s.status = SolveStatus::kIllConditioned;
      s.message = buf;
    }
  }
  if (!p.has_friction() && s.status != SolveStatus::kConverged &&
      s.status != SolveStatus::kCycling && s.status != SolveStatus::kMaxIterations) {
    s.u = VecX::Zero(p.num_unknowns());  // nothing of a failed solve is returned as a state
    s.contact_force = VecX();
    s.eq_multiplier = VecX();
    s.active.clear();
  }
  s.penalty = k_gap;
  return s;
}

}  // namespace c2d::constraints
