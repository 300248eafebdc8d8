#include "constraints/methods/penalty_strategy.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "constraints/friction_solver.hpp"
#include "constraints/strategy_common.hpp"

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

/// How far the forces that the penalty's equations give from u, −k g(u) on the rows carrying
/// force and −k h(u) on the equality rows, stand from the solve's own forces (exact to the
/// dense block's precision): the round-off that k lends them.
double force_round_off(const ConstrainedProblem& p, const ConstraintSolution& s,
                       const VecX& k_gap, const VecX& k_eq) {
  double largest = 0.0;
  if (s.contact_force.size() == p.num_gaps()) {
    const VecX g = p.gap0 + p.gap_jacobian * s.u;
    for (int i = 0; i < p.num_gaps(); ++i)
      if (s.contact_force[i] > 0)
        largest = std::max(largest, std::abs(-k_gap[i] * g[i] - s.contact_force[i]));
  }
  if (s.eq_multiplier.size() == p.num_equalities() && p.num_equalities() > 0) {
    const VecX h = p.eq_jacobian * s.u - p.eq_rhs;
    for (int j = 0; j < p.num_equalities(); ++j)
      largest = std::max(largest, std::abs(-k_eq[j] * h[j] - s.eq_multiplier[j]));
  }
  return largest;
}

/// The largest ratio, over the rows carrying force w (above 1e-6 of the largest), of a gap's
/// round-off, 16 ε (|g0| + Σ|G_ij u_j|), to the penetration w/k that the penalty leaves it:
/// above 1 the penetration is below what the gaps resolve, so the set decisions read noise.
double unresolved_penetration(const ConstrainedProblem& p, const VecX& w, const VecX& k_gap,
                              const VecX& u) {
  const int m = p.num_gaps();
  if (m == 0 || w.size() != m || u.size() != p.num_unknowns()) return 0.0;
  const double significant = 1e-6 * w.cwiseAbs().maxCoeff();
  const VecX spread = p.gap_jacobian.cwiseAbs() * u.cwiseAbs();
  double worst = 0.0;
  for (int i = 0; i < m; ++i) {
    if (!(w[i] > significant)) continue;
    const double round_off =
        16 * std::numeric_limits<double>::epsilon() * (std::abs(p.gap0[i]) + spread[i]);
    worst = std::max(worst, round_off / (w[i] / k_gap[i]));
  }
  return worst;
}
}  // namespace

ConstraintSolution PenaltyStrategy::solve_problem(const ConstrainedProblem& p,
                                                  const RowMemory& memory) {
  ConstraintSolution s;
  VecX k_gap, k_eq;
  default_penalties(p, memory, options_.penalty_k, options_.penalty_factor, k_gap, k_eq);
  const VecX zero_gap = VecX::Zero(p.num_gaps()), zero_eq = VecX::Zero(p.num_equalities());
  FrictionalOptions o = penalised_friction(set_rule(), p, memory, k_gap, zero_gap, k_eq, zero_eq);
  o.max_iterations = options_.max_iterations;
  solve_frictional(p, memory, o, s);
  const bool solved = s.status == SolveStatus::kConverged ||
                      s.status == SolveStatus::kCycling || s.status == SolveStatus::kMaxIterations;
  // A penalty many orders above the element stiffness: say so instead of returning what it
  // produced when its digits are gone. The condensed solve keeps its forces' digits, but the
  // forces k·g that the run's Newton and report take from the gaps carry the gaps' round-off
  // times k: measured as their distance from the solve's own forces.
  const double ratio = penalty_ratio(p, memory, k_gap, k_eq);
  if (ratio > 1e6 && solved) {
    double force = 0.0;
    if (s.contact_force.size()) force = s.contact_force.cwiseAbs().maxCoeff();
    if (s.eq_multiplier.size()) force = std::max(force, s.eq_multiplier.cwiseAbs().maxCoeff());
    const double round_off = force_round_off(p, s, k_gap, k_eq);
    const double unresolved = unresolved_penetration(p, s.contact_force, k_gap, s.u);
    if (force > 0 && (round_off > kForceDigits * force || unresolved > 1.0)) {
      char buf[320];
      if (unresolved > 1.0)
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
  s.penalty = k_gap;
  s.eq_penalty = k_eq;
  return s;
}

}  // namespace c2d::constraints
