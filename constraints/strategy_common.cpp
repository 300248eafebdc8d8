#include "constraints/strategy_common.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "constraints/saddle_point_solver.hpp"

namespace c2d::constraints {

VecX ConstrainedProblem::row_stiffness(const SpMat& rows) const {
  const VecX diag = stiffness.diagonal();
  VecX num = VecX::Zero(rows.rows()), den = VecX::Zero(rows.rows());
  for (int col = 0; col < rows.outerSize(); ++col)
    for (SpMat::InnerIterator it(rows, col); it; ++it) {
      const double a2 = it.value() * it.value();
      num[it.row()] += a2 * diag[it.col()];
      den[it.row()] += a2;
    }
  VecX out(rows.rows());
  for (int i = 0; i < rows.rows(); ++i) out[i] = den[i] > 0 ? num[i] / den[i] : 0.0;
  return out;
}

SpMat stack_rows(const SpMat& top, const SpMat& bottom) {
  std::vector<Triplet> t;
  t.reserve(top.nonZeros() + bottom.nonZeros());
  for (int c = 0; c < top.outerSize(); ++c)
    for (SpMat::InnerIterator it(top, c); it; ++it) t.emplace_back(it.row(), c, it.value());
  for (int c = 0; c < bottom.outerSize(); ++c)
    for (SpMat::InnerIterator it(bottom, c); it; ++it)
      t.emplace_back(top.rows() + it.row(), c, it.value());
  SpMat out(top.rows() + bottom.rows(), std::max(top.cols(), bottom.cols()));
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

bool ConstrainedProblem::frictional(int i) const {
  return static_cast<int>(friction_law.size()) == num_gaps() && slip0.size() == num_gaps() &&
         friction_law[i] != nullptr;
}

FrictionBound ConstrainedProblem::friction_bound(int i, double normal_force) const {
  const double area = gap_area.size() == num_gaps() ? gap_area[i] : 0.0;
  return friction_law[i]->bound(std::max(0.0, normal_force), area);
}

double ConstrainedProblem::friction_limit(int i, double normal_force) const {
  return friction_bound(i, normal_force).at(std::max(0.0, normal_force));
}

bool ConstrainedProblem::friction_binds_open(int i) const {
  return frictional(i) && friction_limit(i, 0.0) > 0;
}

bool ConstrainedProblem::has_friction() const {
  for (int i = 0; i < num_gaps(); ++i)
    if (frictional(i)) return true;
  return false;
}

VecX ConstrainedProblem::gap_local_stiffness(const RowMemory& memory) const {
  return memory.gap_row_stiffness.size() == num_gaps() ? memory.gap_row_stiffness
                                                       : surface_stiffness();
}

VecX ConstrainedProblem::surface_stiffness() const {
  const int m = num_gaps();
  VecX local = row_stiffness(gap_jacobian);
  if (gap_area.size() != m || gap_node_area.size() != m || static_cast<int>(gap_surface.size()) != m)
    return local;
  // κ per surface over its slave nodes' whole areas: a mortar row cut short by the master's
  // end has a sliver of weight, and its stiffness over that sliver is no measure of the surface.
  std::vector<double> kappa;
  for (int i = 0; i < m; ++i) {
    const int s = gap_surface[i];
    if (s < 0 || !(gap_node_area[i] > 0) || !(local[i] > 0)) continue;
    if (s >= static_cast<int>(kappa.size())) kappa.resize(s + 1, 0.0);
    kappa[s] = std::max(kappa[s], local[i] / gap_node_area[i]);
  }
  for (int i = 0; i < m; ++i) {
    const int s = gap_surface[i];
    if (s >= 0 && s < static_cast<int>(kappa.size()) && kappa[s] > 0 && gap_area[i] > 0)
      local[i] = kappa[s] * gap_area[i];
  }
  return local;
}

double penetration_tolerance(const StrategyOptions& o, double length_scale) {
  return o.tolerance > 0 ? o.tolerance : o.relative_tolerance * length_scale;
}

double penetration_tolerance(const StrategyOptions& o, const ConstrainedProblem& p) {
  return penetration_tolerance(o, p.length_scale);
}

double touch_tolerance(const ConstrainedProblem& p) { return 1e-12 * p.model_size; }

RuleScales rule_scales(const ConstrainedProblem& p, double force_scale, double c) {
  RuleScales s;
  s.gap_tolerance = touch_tolerance(p);
  s.force_tolerance = 1e-10 * std::max({force_scale, c * s.gap_tolerance, 1e-300});
  s.c = c;
  return s;
}

double next_normal_set(const SetRule& rule, const ConstrainedProblem& p, const VecX& force,
                       const VecX& gap, const VecX& penalty, const VecX& estimate, double c,
                       std::vector<char>& next) {
  const int m = p.num_gaps();
  std::vector<char> closable(m, 0);
  for (int k = 0; k < p.gap_jacobian.outerSize(); ++k)
    for (SpMat::InnerIterator it(p.gap_jacobian, k); it; ++it) closable[it.row()] = 1;
  const RuleScales scales =
      rule_scales(p, force.size() > 0 ? force.cwiseAbs().maxCoeff() : 0.0, c);
  const bool regularised = penalty.size() == m && estimate.size() == m;
  double residual = 0.0;
  for (int i = 0; i < m; ++i) {
    RowSolution r;
    r.force = force.size() == m ? force[i] : 0.0;
    r.gap = gap[i];
    r.held = next[i] != 0;
    r.closable = closable[i] != 0;
    if (regularised) r.penalty = penalty[i], r.force_estimate = estimate[i];
    const NormalDecision d = rule.normal(r, scales);
    next[i] = d.held;
    residual = std::max(residual, d.residual);
  }
  return residual;
}

std::vector<char> initially_closed(const ConstrainedProblem& p, const RowMemory& memory) {
  if (static_cast<int>(memory.initial_active.size()) == p.num_gaps()) return memory.initial_active;
  std::vector<char> active(p.num_gaps(), 0);
  const double touch = touch_tolerance(p);
  for (int i = 0; i < p.num_gaps(); ++i) active[i] = p.gap0[i] <= touch;
  return active;
}

double max_penetration(const VecX& gap) {
  return gap.size() > 0 ? std::max(0.0, -gap.minCoeff()) : 0.0;
}

IterationRecord make_record(int iteration, const std::vector<char>& next,
                            const ActiveSetTracker::Change& change, const VecX& gap,
                            double residual) {
  IterationRecord rec;
  rec.iteration = iteration;
  rec.active = count_active(next);
  rec.entering = change.entering;
  rec.leaving = change.leaving;
  rec.max_penetration = max_penetration(gap);
  rec.residual = residual;
  return rec;
}

void finish_solution(const ConstrainedProblem& p, ConstraintSolution& s) {
  const int m = p.num_gaps();
  if (s.u.size() != p.num_unknowns()) s.u = VecX::Zero(p.num_unknowns());
  if (s.contact_force.size() != m) s.contact_force = VecX::Zero(m);
  if (s.eq_multiplier.size() != p.num_equalities())
    s.eq_multiplier = VecX::Zero(p.num_equalities());
  if (s.penalty.size() != m) s.penalty = VecX::Zero(m);
  if (s.eq_penalty.size() != p.num_equalities()) s.eq_penalty = VecX::Zero(p.num_equalities());
  if (static_cast<int>(s.active.size()) != m) s.active.assign(m, 0);
  const bool friction = p.has_friction();
  if (friction) {
    if (s.tangent_force.size() != m) s.tangent_force = VecX::Zero(m);
    if (static_cast<int>(s.friction_state.size()) != m)
      s.friction_state.assign(m, FrictionState::kOpen);
  }
  const bool finite = s.u.allFinite() && s.contact_force.allFinite() &&
                      s.eq_multiplier.allFinite() && s.penalty.allFinite() &&
                      s.tangent_force.allFinite();
  if (!finite) {
    s.status = SolveStatus::kFailed;
    s.message = "non-finite values in the solution" + (s.message.empty() ? "" : ": " + s.message);
    s.u.setZero();
    s.contact_force.setZero();
    s.eq_multiplier.setZero();
    s.penalty.setZero();
    s.tangent_force.setZero();
  }
  if (friction) s.slip = p.slip0 + p.slip_jacobian * s.u;
  s.gap = m > 0 ? VecX(p.gap0 + p.gap_jacobian * s.u) : VecX();
  s.max_penetration = max_penetration(s.gap);
  s.max_eq_violation =
      p.num_equalities() > 0 ? (p.eq_jacobian * s.u - p.eq_rhs).cwiseAbs().maxCoeff() : 0.0;
  if (!s.history.empty()) s.iterations = s.history.back().iteration;
}

namespace {


IterationRecord safeguard_record(int iteration, const std::vector<char>& active, int entering,
                                 int leaving, const VecX& gap) {
  ActiveSetTracker::Change change;
  change.entering = entering;
  change.leaving = leaving;
  return make_record(iteration, active, change, gap, 0.0);
}

}  // namespace

SolveStatus dual_active_set(const ConstrainedProblem& p, const SetSolve& solve_set,
                            const VecX& shift, int max_steps, int iteration,
                            std::vector<char>& active, ConstraintSolution& s,
                            std::string& message) {
  const int m = p.num_gaps();
  const double gap_tol = touch_tolerance(p);
  auto gap_of = [&](const VecX& u) { return VecX(p.gap0 + p.gap_jacobian * u); };
  // 1. A set whose forces are all compressive: drop the rows in tension (the set shrinks, so
  //    this ends, at worst with no rows).
  for (;;) {
    if (const SolveStatus st = solve_set(active, s, message); st != SolveStatus::kConverged) {
      message = "safeguard: " + message;
      return st;
    }
    const double tol =
        1e-10 * std::max(m > 0 ? s.contact_force.cwiseAbs().maxCoeff() : 0.0, 1e-300);
    int leaving = 0;
    for (int i = 0; i < m; ++i)
      if (active[i] && s.contact_force[i] < -tol) active[i] = 0, ++leaving;
    if (leaving == 0) break;
    s.history.push_back(safeguard_record(++iteration, active, 0, leaving, gap_of(s.u)));
  }
  for (int i = 0; i < m; ++i)
    s.contact_force[i] = active[i] ? std::max(0.0, s.contact_force[i]) : 0.0;
  // 2. The most penetrating rows added one at a time.
  int q = -1;  // the row being added, when a step stopped short of closing it
  ConstraintSolution target;
  for (int step = 1; step <= max_steps; ++step) {
    const VecX g = gap_of(s.u);
    if (q < 0) {
      for (int i = 0; i < m; ++i)
        if (!active[i] && g[i] - shift[i] < -gap_tol &&
            (q < 0 || g[i] - shift[i] < g[q] - shift[q]))
          q = i;
      if (q < 0) return SolveStatus::kConverged;
    }
    std::vector<char> trial = active;
    trial[q] = 1;
    if (const SolveStatus st = solve_set(trial, target, message); st != SolveStatus::kConverged) {
      message = "safeguard: " + message;
      return st;
    }
    // Along the path λ_q grows; if it cannot, row q depends on the active rows.
    if (!(target.contact_force[q] > s.contact_force[q])) {
      message = "safeguard: penetrating row " + std::to_string(q) +
                " takes no force beside the active rows (redundant rows)";
      return SolveStatus::kSingular;
    }
    double tau = 1.0;
    int blocking = -1;
    for (int i = 0; i < m; ++i)
      if (active[i] && i != q && target.contact_force[i] < 0.0) {
        const double t = s.contact_force[i] / (s.contact_force[i] - target.contact_force[i]);
        if (t < tau) tau = t, blocking = i;
      }
    s.u += tau * (target.u - s.u);
    if (s.eq_multiplier.size() > 0)
      s.eq_multiplier += tau * (target.eq_multiplier - s.eq_multiplier);
    s.contact_force += tau * (target.contact_force - s.contact_force);
    int entering = 0, leaving = 0;
    if (blocking >= 0) {
      active[blocking] = 0, ++leaving;
    } else {
      active[q] = 1, ++entering;
      q = -1;
    }
    for (int i = 0; i < m; ++i)
      s.contact_force[i] = active[i] || i == q ? std::max(0.0, s.contact_force[i]) : 0.0;
    s.history.push_back(safeguard_record(++iteration, active, entering, leaving, gap_of(s.u)));
  }
  if (q >= 0) active[q] = s.contact_force[q] > 0;
  message = "safeguard: rows still penetrating after " + std::to_string(max_steps) +
            " dual active-set steps";
  return SolveStatus::kMaxIterations;
}

void add_solution_work(const ConstraintSolution& from, ConstraintSolution& to) {
  to.factorizations += from.factorizations;
  to.symbolic_analyses += from.symbolic_analyses;
  to.symbolic_seconds += from.symbolic_seconds;
  to.numeric_seconds += from.numeric_seconds;
  to.solve_seconds += from.solve_seconds;
}

double saddle_point_scale(const ConstrainedProblem& p) {
  const VecX d = p.stiffness.diagonal().cwiseAbs();
  const double s = d.size() > 0 ? d.mean() : 1.0;
  return s > 0 ? s : 1.0;
}

std::vector<int> gap_positions(const ConstrainedProblem& p, const std::vector<char>& active,
                               bool all_rows, int& size) {
  std::vector<int> pos(p.num_gaps(), -1);
  size = p.num_unknowns() + p.num_equalities();
  for (int i = 0; i < p.num_gaps(); ++i)
    if (all_rows || active[i]) pos[i] = size++;
  return pos;
}

VecX saddle_point_rhs(const ConstrainedProblem& p, const std::vector<char>& active, double s,
                      bool all_rows) {
  const int n = p.num_unknowns(), me = p.num_equalities();
  int size = 0;
  const auto pos = gap_positions(p, active, all_rows, size);
  VecX b = VecX::Zero(size);
  b.head(n) = p.load;
  if (me > 0) b.segment(n, me) = -s * p.eq_rhs;
  for (int i = 0; i < p.num_gaps(); ++i)
    if (pos[i] >= 0 && active[i]) b[pos[i]] = s * p.gap0[i];
  return b;
}

SpMat saddle_point_matrix(const ConstrainedProblem& p, const std::vector<char>& active, double s,
                          bool all_rows) {
  const int n = p.num_unknowns();
  int size = 0;
  const auto pos = gap_positions(p, active, all_rows, size);
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(p.stiffness.nonZeros() + 2 * (p.eq_jacobian.nonZeros() + p.gap_jacobian.nonZeros()) +
            p.num_gaps());
  for (int c = 0; c < p.stiffness.outerSize(); ++c)
    for (SpMat::InnerIterator it(p.stiffness, c); it; ++it)
      t.emplace_back(it.row(), it.col(), it.value());
  for (int c = 0; c < p.eq_jacobian.outerSize(); ++c)
    for (SpMat::InnerIterator it(p.eq_jacobian, c); it; ++it) {
      t.emplace_back(n + it.row(), it.col(), -s * it.value());
      t.emplace_back(it.col(), n + it.row(), -s * it.value());
    }
  for (int c = 0; c < p.gap_jacobian.outerSize(); ++c)
    for (SpMat::InnerIterator it(p.gap_jacobian, c); it; ++it) {
      const int q = pos[it.row()];
      if (q < 0) continue;
      const double v = active[it.row()] ? -s * it.value() : 0.0;
      t.emplace_back(q, it.col(), v);
      t.emplace_back(it.col(), q, v);
    }
  if (all_rows)
    for (int i = 0; i < p.num_gaps(); ++i) t.emplace_back(pos[i], pos[i], active[i] ? 0.0 : s);
  SpMat m(size, size);
  m.setFromTriplets(t.begin(), t.end());
  return m;
}

}  // namespace c2d::constraints
