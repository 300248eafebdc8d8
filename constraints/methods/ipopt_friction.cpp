// ipopt with friction: a fixed point of Tresca problems, each a QP in which the friction cone's
// two faces are linear inequalities, finished by a crossover (ipopt_qp.hpp).
#include <algorithm>
#include <cmath>

#include "constraints/friction_solver.hpp"
#include "constraints/methods/ipopt_qp.hpp"
#include "constraints/strategy_common.hpp"

namespace c2d::constraints::ipopt_detail {

namespace {

/// Gap row i's tangential row times `sign` (column i of tt = Tᵀ), with coefficient 1 on the
/// auxiliary variable `aux` when it is ≥ 0, normalised to unit length like every kept row.
KeptRow tangential_row(const SpMat& tt, int i, double sign, int aux) {
  KeptRow k;
  k.source = i;
  double n2 = 0.0;
  if (aux >= 0) k.terms.emplace_back(aux, 1.0), n2 = 1.0;
  for (SpMat::InnerIterator it(tt, i); it; ++it) {
    k.terms.emplace_back(static_cast<int>(it.row()), sign * it.value());
    n2 += it.value() * it.value();
  }
  k.norm = std::sqrt(n2);
  for (auto& [c, v] : k.terms) v /= k.norm;
  return k;
}

/// A Tresca problem's rows: for each gap row i with a bound b_i > 0 and a tangential row, an
/// auxiliary p_k ≥ |s_i| as p_k − s_i ≥ 0 (kept with friction = +1) and p_k + s_i ≥ 0 (−1),
/// over x = [u; p], normalised like the others. Returns the costs b of the p.
VecX add_tresca_rows(const ConstrainedProblem& p, const VecX& bound, RowSet& rows,
                     std::vector<int>& friction_sign) {
  const SpMat tt = p.slip_jacobian.transpose();
  std::vector<double> cost;
  friction_sign.assign(rows.rows.size(), 0);
  for (int i = 0; i < p.num_gaps(); ++i) {
    if (!(bound[i] > 0) || tt.col(i).nonZeros() == 0) continue;
    const int aux = p.num_unknowns() + static_cast<int>(cost.size());
    cost.push_back(bound[i]);
    for (const int sign : {+1, -1}) {
      KeptRow k = tangential_row(tt, i, -sign, aux);
      k.lower = sign * p.slip0[i] / k.norm;  // p − sign·(s0 + T u) ≥ 0
      k.upper = 2e19;
      rows.rows.push_back(k);
      friction_sign.push_back(sign);
    }
  }
  return Eigen::Map<const VecX>(cost.data(), static_cast<Eigen::Index>(cost.size()));
}

/// The first problem of a Coulomb fixed point without normal forces to start from: the rows
/// closed at the start (`memory`'s) stick (T_i u = −s0_i, an equality; friction_sign 2), which
/// holds a body that only friction holds sideways (a frictionless first problem would let it
/// slide away).
void add_stick_rows(const ConstrainedProblem& p, const RowMemory& memory, RowSet& rows,
                    std::vector<int>& friction_sign) {
  const SpMat tt = p.slip_jacobian.transpose();
  const std::vector<char> closed = initially_closed(p, memory);
  friction_sign.resize(rows.rows.size(), 0);
  for (int i = 0; i < p.num_gaps(); ++i) {
    if (!closed[i] || tt.col(i).nonZeros() == 0 || !p.frictional(i)) continue;
    KeptRow k = tangential_row(tt, i, 1.0, -1);
    k.equality = true;
    k.lower = k.upper = -p.slip0[i] / k.norm;
    rows.rows.push_back(k);
    friction_sign.push_back(2);
  }
}

/// The largest number of exact solves in a crossover.
constexpr int kCrossoverIterations = 4;

/// The crossover of an interior point, as an LP barrier's crossover pivots to a basis
/// (confirm_exactly, friction_solver.hpp). An interior point stops a barrier parameter away
/// from the solution, so a row at the edge of its cone can be classified on the wrong side of
/// it; the rule may move such rows for up to kCrossoverIterations − 1 further solves. Without
/// the crossover, a sticking row's degenerate faces and the slip forces' bound keep O(tol)
/// errors that move from one solve to the next, so a load step's outer iterations, which ask
/// for the same state twice, would not settle.
bool crossover(FrictionalSolver& solver, ConstraintSolution& s, std::string& why) {
  return confirm_exactly(solver, kCrossoverIterations, s, why);
}

/// The active rows of an Ipopt solution and each one's stick or slip: slip where its force
/// reached `bound` (to 1e-6).
void classify(const ConstrainedProblem& p, const StrategyOptions& o, const VecX& bound,
              ConstraintSolution& s) {
  settle_active_set(p, o, s, false);
  s.friction_state.assign(p.num_gaps(), FrictionState::kOpen);
  for (int i = 0; i < p.num_gaps(); ++i)
    if (s.active[i])
      s.friction_state[i] = bound[i] > 0 && std::abs(s.tangent_force[i]) < (1 - 1e-6) * bound[i]
                                ? FrictionState::kStick
                                : FrictionState::kSlip;
}

/// Each frictional row's bound at the given normal force (its law's).
VecX friction_bounds(const ConstrainedProblem& p, const VecX& normal) {
  VecX b = VecX::Zero(p.num_gaps());
  for (int i = 0; i < p.num_gaps(); ++i)
    if (p.frictional(i)) b[i] = p.friction_limit(i, normal[i]);
  return b;
}

/// The solution's normal forces on `rows` (those that hold it), zero on the others: an interior
/// point leaves O(μ_barrier / gap) forces on open rows, which would otherwise keep the bounds
/// moving.
VecX forces_on(const ConstraintSolution& s, const std::vector<char>& rows) {
  VecX normal = s.contact_force;
  for (int i = 0; i < normal.size(); ++i)
    if (!rows[i]) normal[i] = 0.0;
  return normal;
}

}  // namespace

std::string solve_tresca_fixed_point(const ConstrainedProblem& p, const RowMemory& memory,
                                     const StrategyOptions& o, const RowSet& base,
                                     FrictionalSolver& solver, bool try_surface,
                                     ConstraintSolution& s, int& total_iterations, VecX& bound,
                                     bool& exact, bool& on_surface) {
  // Each problem is a QP whose friction forces a row's bound b (μ λ for Coulomb) limits; the
  // bound comes from the normal force of the previous QP (the first sees the warm start's
  // forces, or none), and the iteration ends when no bound changes by more than 1e-9 of the
  // largest. On the surface (SurfaceDual) each problem is the dual with |w_t| ≤ b, K factorised
  // once for all of them; otherwise the primal on the whole KKT system, the cone's two faces as
  // the linear inequalities p ≥ ±s with cost b p.
  bound = friction_bounds(p, memory.initial_force.size() == p.num_gaps()
                                 ? memory.initial_force
                                 : VecX(VecX::Zero(p.num_gaps())));
  // No normal force to start from: the first problem holds the closed rows sticking.
  bool stick_first = bound.lpNorm<Eigen::Infinity>() == 0.0;
  total_iterations = 0;
  exact = false;
  s.status = SolveStatus::kMaxIterations;
  const std::unique_ptr<SurfaceDual> dual =
      try_surface ? SurfaceDual::build(p, base, true, s) : nullptr;
  on_surface = dual != nullptr;
  // The crossover solves on the dual's factor (its rows appended), not on one of its own.
  if (dual) solver.share(dual->surface());
  const std::vector<char> closed = initially_closed(p, memory);
  struct Report {  // the surface's factorisation into s on every way out
    const SurfaceDual* dual;
    ConstraintSolution& s;
    ~Report() { if (dual) dual->report(s); }
  } report{dual.get(), s};
  for (int round = 1; round <= o.max_iterations; ++round) {
    // A sticking row holds p = |s| = 0 with both faces active (degenerate): the barrier leaves
    // a slip of O(tol) there, which its tangential stiffness turns into force errors of 1e-4
    // at tol = 1e-10. The crossover after each problem makes the forces exact once its sets
    // are right. (Solving the problems to 1e-2 of the tolerance instead, as before, ended the
    // Cattaneo–Mindlin example's first QP with "search direction too small".)
    QpOutcome qp;
    if (dual) {
      std::vector<char> stick(p.num_gaps(), 0);
      for (int i = 0; i < p.num_gaps() && stick_first; ++i)
        stick[i] = closed[i] && p.frictional(i);
      qp = dual->solve(bound, stick, o, o.ipopt_tolerance, s);
    } else {
      RowSet rows = base;
      std::vector<int> friction_sign;
      const VecX cost = add_tresca_rows(p, bound, rows, friction_sign);
      if (stick_first) add_stick_rows(p, memory, rows, friction_sign);
      qp = run_ipopt(p, rows, cost, o, o.ipopt_tolerance);
      extract_forces(p, rows, friction_sign, qp, s);
    }
    total_iterations += qp.iterations;
    IterationRecord rec;
    rec.iteration = total_iterations;
    rec.max_penetration = max_penetration(VecX(p.gap0 + p.gap_jacobian * s.u));
    s.history.push_back(rec);
    // The next bounds at the QP's normal forces on the rows it holds: on the whole system the
    // rows that touch, on the surface the dual's held rows (force against gap, as its classify
    // takes them). There the primal's touch test (gap within 2e-9 at the u rebuilt from the
    // dual's forces) dropped a few rows that carry force each round, which zeroed their bounds
    // and kept the fixed point from settling (ring_plate_drag step 8: a change of ~9 % of the
    // largest bound for all 50 problems, then the whole KKT system, ~150 factorisations an
    // outer iteration).
    if (dual) dual->classify(s);
    const VecX next = friction_bounds(p, forces_on(s, dual ? s.active : touching_rows(p, o, s)));
    // On the surface the dual's own indicators classify the rows first (force against gap,
    // slip against the distance to the bound; no touch tolerance), then, as for the primal,
    // touch and the bounds at the QP's own normal forces. A crossover is dense work only.
    std::string why;
    bool confirmed = false;
    if (dual) confirmed = crossover(solver, s, why);
    if (!confirmed) {
      classify(p, o, next, s);
      confirmed = crossover(solver, s, why);
    }
    if (confirmed) {
      s.status = SolveStatus::kConverged;
      exact = true;
      return "";
    }
    if (qp.status != SolveStatus::kConverged) {
      s.status = qp.status;
      return qp.message;
    }
    const double change = (next - bound).lpNorm<Eigen::Infinity>();
    s.history.back().residual = change;
    const double largest = next.lpNorm<Eigen::Infinity>();
    const bool settled = change <= 1e-9 * std::max(largest, 1e-300) || largest == 0.0;
    bound = next;
    if (stick_first) {  // the sticking problem gave the first normal forces
      stick_first = false;
      continue;
    }
    if (settled && round > 1) {
      s.status = SolveStatus::kConverged;
      return "";
    }
  }
  return "friction bounds still changing after " + std::to_string(o.max_iterations) +
         " Tresca problems";
}

bool finish_friction(const ConstrainedProblem& p, const StrategyOptions& o, const VecX& bound,
                     bool exact, FrictionalSolver& solver, ConstraintSolution& s) {
  if (!exact) {
    classify(p, o, bound, s);
    if (s.status != SolveStatus::kConverged) return false;
    std::string why;
    exact = crossover(solver, s, why);
    if (!exact)
      s.message = "the exact solve of Ipopt's sets did not confirm them (" + why +
                  "): Ipopt's solution, to its tolerance";
  }
  // An exact solution's sets were solved as a saddle point, which is singular when its rows
  // leave a rigid motion free: only Ipopt's own solution needs the check.
  settle_active_set(p, o, s, !exact);
  return exact;
}

}  // namespace c2d::constraints::ipopt_detail
