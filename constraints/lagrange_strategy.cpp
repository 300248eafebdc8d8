#include "constraints/lagrange_strategy.hpp"

#include <chrono>
#include <cmath>

#include "constraints/kkt_solver.hpp"
#include "constraints/strategy_common.hpp"

namespace c2d::constraints {

ConstraintSolution LagrangeStrategy::solve(const ConstrainedProblem& p) {
  const auto t0 = std::chrono::steady_clock::now();
  ConstraintSolution s;
  s.method = name();
  const int m = p.num_gaps();
  const double scale = saddle_point_scale(p);
  const double gap_tol = 1e-12 * p.model_size;
  std::vector<char> active = initially_closed(p);
  ActiveSetTracker tracker;
  tracker.record(active);
  KktSolver kkt;
  s.status = SolveStatus::kMaxIterations;
  s.message = "active set still changing after " + std::to_string(options_.max_iterations) +
              " iterations";
  for (int it = 1; it <= options_.max_iterations; ++it) {
    // The reduced system changes size with the active set, so each iteration analyses anew.
    const SpMat m_kkt = saddle_point_matrix(p, active, scale, false);
    VecX x;
    SolveStatus st = kkt.factorize(m_kkt, false);
    if (st == SolveStatus::kConverged) st = kkt.solve(saddle_point_rhs(p, active, scale, false), x);
    if (st != SolveStatus::kConverged) {
      s.status = st;
      s.message = kkt.report().message;
      s.iterations = it;
      break;
    }
    split_saddle_point(p, active, scale, false, x, s);
    const VecX g = m > 0 ? VecX(p.gap0 + p.gap_jacobian * s.u) : VecX();
    const double force_tol =
        1e-10 * (m > 0 ? std::max(s.contact_force.cwiseAbs().maxCoeff(), 1e-300) : 1.0);
    std::vector<char> next = active;
    for (int i = 0; i < m; ++i) {
      if (active[i] && s.contact_force[i] < -force_tol) next[i] = 0;  // tension: release
      if (!active[i] && g[i] < -gap_tol) next[i] = 1;                 // penetration: close
    }
    const auto change = tracker.record(next);
    IterationRecord rec;
    rec.iteration = it;
    rec.active = count_active(next);
    rec.entering = change.entering;
    rec.leaving = change.leaving;
    rec.max_penetration = m > 0 ? std::max(0.0, -g.minCoeff()) : 0.0;
    rec.residual = kkt.report().relative_residual;
    s.history.push_back(rec);
    if (change.unchanged) {
      s.status = SolveStatus::kConverged;
      s.message.clear();
      break;
    }
    if (change.repeated) {
      s.status = SolveStatus::kCycling;
      s.message = "active set returned to an earlier set at iteration " + std::to_string(it);
      break;
    }
    active = next;
  }
  s.active = active;
  s.factorizations = kkt.report().numeric_factorizations;
  if (s.status != SolveStatus::kConverged && s.status != SolveStatus::kCycling &&
      s.status != SolveStatus::kMaxIterations)
    s.u = VecX::Zero(p.num_unknowns());
  finish_solution(p, s);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return s;
}

}  // namespace c2d::constraints
