#include "constraints/ssn_strategy.hpp"

#include <chrono>
#include <cmath>

#include "constraints/kkt_solver.hpp"
#include "constraints/strategy_common.hpp"

namespace c2d::constraints {

ConstraintSolution SsnStrategy::solve(const ConstrainedProblem& p) {
  const auto t0 = std::chrono::steady_clock::now();
  ConstraintSolution s;
  s.method = name();
  const int m = p.num_gaps();
  // c has the units of a stiffness, so λ − c g compares a force with a force.
  const double scale = saddle_point_scale(p);
  const double c = scale;
  std::vector<char> active = initially_closed(p);
  ActiveSetTracker tracker;
  tracker.record(active);
  KktSolver kkt;
  s.status = SolveStatus::kMaxIterations;
  s.message = "active set still changing after " + std::to_string(options_.max_iterations) +
              " Newton steps";
  for (int it = 1; it <= options_.max_iterations; ++it) {
    VecX x;
    SolveStatus st = kkt.factorize(saddle_point_matrix(p, active, scale, true), it > 1);
    if (st == SolveStatus::kConverged) st = kkt.solve(saddle_point_rhs(p, active, scale, true), x);
    if (st != SolveStatus::kConverged) {
      s.status = st;
      s.message = kkt.report().message;
      break;
    }
    split_saddle_point(p, active, scale, true, x, s);
    const VecX g = m > 0 ? VecX(p.gap0 + p.gap_jacobian * s.u) : VecX();
    const double lmax = m > 0 ? s.contact_force.cwiseAbs().maxCoeff() : 0.0;
    const double eps = 1e-10 * std::max(lmax, c * 1e-12 * p.model_size);
    std::vector<char> next(m, 0);
    double complementarity = 0.0;
    for (int i = 0; i < m; ++i) {
      next[i] = s.contact_force[i] - c * g[i] > eps;
      complementarity = std::max(
          complementarity, std::abs(s.contact_force[i] - std::max(0.0, s.contact_force[i] - c * g[i])));
    }
    const auto change = tracker.record(next);
    IterationRecord rec;
    rec.iteration = it;
    rec.active = count_active(next);
    rec.entering = change.entering;
    rec.leaving = change.leaving;
    rec.max_penetration = m > 0 ? std::max(0.0, -g.minCoeff()) : 0.0;
    rec.residual = complementarity;
    s.history.push_back(rec);
    if (change.unchanged) {
      s.status = SolveStatus::kConverged;
      s.message.clear();
      break;
    }
    if (change.repeated) {
      s.status = SolveStatus::kCycling;
      s.message = "active set returned to an earlier set at Newton step " + std::to_string(it);
      break;
    }
    active = next;
  }
  s.active = active;
  s.factorizations = kkt.report().numeric_factorizations;
  if (s.status == SolveStatus::kSingular || s.status == SolveStatus::kFailed ||
      s.status == SolveStatus::kIllConditioned)
    s.u = VecX::Zero(p.num_unknowns());
  finish_solution(p, s);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return s;
}

}  // namespace c2d::constraints
