#include "constraints/methods/ipopt_strategy.hpp"

#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>
#include <cmath>
#include <map>
#include <sstream>

#include "core/interrupt.hpp"
#include "core/spd_solver.hpp"
#include "constraints/methods/ipopt_qp.hpp"
#include "constraints/strategy_common.hpp"

namespace c2d::constraints {

namespace ipopt_detail {

using Ipopt::Index;
using Ipopt::Number;

/// Normalises the rows and drops zero rows and duplicates (the tightest copy of a gap row is
/// kept; duplicate equalities must agree).
RowSet prepare_rows(const ConstrainedProblem& p) {
  RowSet out;
  std::map<std::string, int> seen;  // pattern+coefficients -> kept row
  auto add = [&](const SpMat& rows_t, int r, bool equality, double rhs) {
    KeptRow k;
    k.equality = equality;
    k.source = r;
    double n2 = 0;
    for (SpMat::InnerIterator it(rows_t, r); it; ++it) {
      if (it.value() == 0.0) continue;
      k.terms.emplace_back(static_cast<int>(it.row()), it.value());
      n2 += it.value() * it.value();
    }
    k.norm = std::sqrt(n2);
    if (k.norm == 0.0) {
      if (equality ? rhs != 0.0 : rhs > 0.0)
        out.inconsistent = std::string(equality ? "equality" : "gap") + " row " +
                           std::to_string(r) + " has no coefficients but cannot be satisfied";
      ++out.dropped_zero;
      return;
    }
    std::ostringstream key;
    key.precision(10);
    key << equality << ':';
    for (auto& [c, v] : k.terms) {
      v /= k.norm;
      key << c << '/' << v << ';';
    }
    if (equality) k.lower = k.upper = rhs / k.norm;
    else k.lower = rhs / k.norm, k.upper = 2e19;  // -g0/|G| <= G u/|G|
    const auto [pos, fresh] = seen.emplace(key.str(), static_cast<int>(out.rows.size()));
    if (!fresh) {
      KeptRow& first = out.rows[pos->second];
      ++out.dropped_duplicate;
      if (equality && std::abs(first.lower - k.lower) > 1e-12 * (1 + std::abs(k.lower)))
        out.inconsistent = "equality rows " + std::to_string(first.source) + " and " +
                           std::to_string(r) + " are parallel with different right-hand sides";
      if (!equality && k.lower > first.lower) first.lower = k.lower, first.source = r;
      return;
    }
    out.rows.push_back(k);
  };
  const SpMat at = p.eq_jacobian.transpose(), gt = p.gap_jacobian.transpose();
  for (int j = 0; j < p.num_equalities(); ++j) add(at, j, true, p.eq_rhs[j]);
  for (int i = 0; i < p.num_gaps(); ++i) add(gt, i, false, -p.gap0[i]);
  return out;
}

bool QpTnlp::get_starting_point(Index n, bool init_x, Number* x0, bool, Number*, Number*, Index,
                                bool, Number*) {
  if (init_x)
    for (Index i = 0; i < n; ++i) x0[i] = 0.0;
  return true;
}

bool QpTnlp::intermediate_callback(Ipopt::AlgorithmMode, Index, Number, Number, Number, Number,
                                   Number, Number, Number, Number, Index,
                                   const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) {
  return !core::interrupt_requested();  // Ipopt stops; the caller unwinds after it returns
}

void QpTnlp::finalize_solution(Ipopt::SolverReturn, Index n, const Number* xp, const Number*,
                               const Number*, Index m, const Number*, const Number* lam, Number,
                               const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) {
  x = Eigen::Map<const VecX>(xp, n);
  lambda = Eigen::Map<const VecX>(lam, m);
}

/// The QP over x = [u; p]: ½uᵀKu − fᵀu + cᵀp, where p are auxiliary variables with linear cost
/// c (the Tresca problem's |s_i| ≤ p_i, cost b_i; none without friction).
class ContactQp : public QpTnlp {
 public:
  ContactQp(const ConstrainedProblem& p, const RowSet& rows, const VecX& cost)
      : p_(p), rows_(rows), cost_(cost) {
    for (int c = 0; c < p.stiffness.outerSize(); ++c)
      for (SpMat::InnerIterator it(p.stiffness, c); it; ++it)
        if (it.row() >= it.col()) hess_.emplace_back(it.row(), it.col(), it.value());
    for (size_t r = 0; r < rows.rows.size(); ++r)
      jac_nnz_ += static_cast<Index>(rows.rows[r].terms.size());
  }

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac, Index& nnz_h,
                    IndexStyleEnum& style) override {
    n = p_.num_unknowns() + static_cast<Index>(cost_.size());
    m = static_cast<Index>(rows_.rows.size());
    nnz_jac = jac_nnz_;
    nnz_h = static_cast<Index>(hess_.size());
    style = C_STYLE;
    return true;
  }
  bool get_bounds_info(Index n, Number* xl, Number* xu, Index m, Number* gl,
                       Number* gu) override {
    for (Index i = 0; i < n; ++i) xl[i] = -2e19, xu[i] = 2e19;
    for (Index r = 0; r < m; ++r) gl[r] = rows_.rows[r].lower, gu[r] = rows_.rows[r].upper;
    return true;
  }
  bool eval_f(Index, const Number* xp, bool, Number& obj) override {
    const int nu = p_.num_unknowns(), np = static_cast<int>(cost_.size());
    const Eigen::Map<const VecX> u(xp, nu), aux(xp + nu, np);
    obj = 0.5 * u.dot(p_.stiffness * u) - p_.load.dot(u) + cost_.dot(aux);
    return std::isfinite(obj);
  }
  bool eval_grad_f(Index, const Number* xp, bool, Number* grad) override {
    const int nu = p_.num_unknowns(), np = static_cast<int>(cost_.size());
    const Eigen::Map<const VecX> u(xp, nu);
    Eigen::Map<VecX>(grad, nu) = p_.stiffness * u - p_.load;
    Eigen::Map<VecX>(grad + nu, np) = cost_;
    return true;
  }
  bool eval_g(Index n, const Number* xp, bool, Index m, Number* g) override {
    for (Index r = 0; r < m; ++r) {
      double v = 0;
      for (const auto& [c, a] : rows_.rows[r].terms) v += a * xp[c];
      g[r] = v;
    }
    (void)n;
    return true;
  }
  bool eval_jac_g(Index, const Number*, bool, Index m, Index, Index* irow, Index* jcol,
                  Number* values) override {
    Index k = 0;
    for (Index r = 0; r < m; ++r)
      for (const auto& [c, a] : rows_.rows[r].terms) {
        if (values) values[k] = a;
        else irow[k] = r, jcol[k] = c;
        ++k;
      }
    return true;
  }
  bool eval_h(Index, const Number*, bool, Number obj_factor, Index, const Number*, bool, Index,
              Index* irow, Index* jcol, Number* values) override {
    for (size_t k = 0; k < hess_.size(); ++k) {
      if (values) values[k] = obj_factor * hess_[k].value();
      else irow[k] = hess_[k].row(), jcol[k] = hess_[k].col();
    }
    return true;
  }
 private:
  const ConstrainedProblem& p_;
  const RowSet& rows_;
  VecX cost_;
  std::vector<Eigen::Triplet<double>> hess_;
  Index jac_nnz_ = 0;
};

SolveStatus map_status(Ipopt::ApplicationReturnStatus s, std::string& message) {
  using A = Ipopt::ApplicationReturnStatus;
  switch (s) {
    case A::Solve_Succeeded: return SolveStatus::kConverged;
    case A::Solved_To_Acceptable_Level:
      message = "Ipopt stopped at its 'acceptable' tolerance";
      return SolveStatus::kConverged;
    case A::Maximum_Iterations_Exceeded:
    case A::Maximum_CpuTime_Exceeded:
      message = "Ipopt reached its iteration or time limit";
      return SolveStatus::kMaxIterations;
    case A::Diverging_Iterates: message = "Ipopt iterates diverged"; return SolveStatus::kDiverged;
    case A::Restoration_Failed:
      message = "Ipopt restoration phase failed (degenerate or nearly dependent constraint rows)";
      return SolveStatus::kIllConditioned;
    case A::Error_In_Step_Computation:
      message = "Ipopt could not compute a step (singular KKT system: an unsupported body or "
                "dependent rows)";
      return SolveStatus::kSingular;
    case A::Infeasible_Problem_Detected:
      message = "Ipopt found the constraints infeasible";
      return SolveStatus::kFailed;
    case A::Search_Direction_Becomes_Too_Small:
      message = "Ipopt search direction became too small";
      return SolveStatus::kIllConditioned;
    default: message = "Ipopt failed with return code " + std::to_string(static_cast<int>(s));
  }
  return SolveStatus::kFailed;
}

/// Whether K + Σ_rows ρ_r c_r c_rᵀ (the held gap rows and every equality row, ρ_r their local
/// stiffness) is positive definite: no rigid motion is left free.
bool holds_every_rigid_motion(const ConstrainedProblem& p, const std::vector<char>& held,
                              const std::vector<FrictionState>* friction = nullptr) {
  const VecX rho_gap = p.row_stiffness(p.gap_jacobian), rho_eq = p.row_stiffness(p.eq_jacobian);
  VecX w_gap = VecX::Zero(p.num_gaps());
  for (int i = 0; i < p.num_gaps(); ++i)
    if (held[i]) w_gap[i] = rho_gap[i] > 0 ? rho_gap[i] : 1.0;
  const SpMat gt = p.gap_jacobian.transpose(), at = p.eq_jacobian.transpose();
  SpMat k = p.stiffness + SpMat(gt * w_gap.asDiagonal() * p.gap_jacobian);
  if (p.num_equalities() > 0)
    k += SpMat(at * rho_eq.cwiseMax(1e-300).asDiagonal() * p.eq_jacobian);
  if (friction) {  // a sticking row holds its tangential direction too
    const VecX rho_t = p.row_stiffness(p.slip_jacobian);
    VecX w_t = VecX::Zero(p.num_gaps());
    for (int i = 0; i < p.num_gaps(); ++i)
      if ((*friction)[i] == FrictionState::kStick) w_t[i] = rho_t[i] > 0 ? rho_t[i] : 1.0;
    k += SpMat(SpMat(p.slip_jacobian.transpose()) * w_t.asDiagonal() * p.slip_jacobian);
  }
  core::SpdSolver spd(core::SpdSolver::Backend::kCholmod, true);
  return spd.factorize(k) == SolveStatus::kConverged;
}

std::vector<char> touching_rows(const ConstrainedProblem& p, const StrategyOptions& o,
                                const ConstraintSolution& s) {
  std::vector<char> touching(p.num_gaps(), 0);
  const double fmax = p.num_gaps() ? s.contact_force.maxCoeff() : 0.0;
  const VecX gap = p.gap0 + p.gap_jacobian * s.u;
  const double touch = penetration_tolerance(o, p);
  for (int i = 0; i < p.num_gaps(); ++i)
    touching[i] = s.contact_force[i] > 1e-6 * fmax && gap[i] <= touch;
  return touching;
}

/// Interior-point iterates leave O(mu / gap) forces on open rows: not contact. A row is active
/// when it carries force and touches (gap within the penetration tolerance); the others are
/// open and their residual forces are dropped. An interior-point method returns some minimiser
/// even when the problem has a line of them (a body pulled off its only support moves by an
/// arbitrary rigid motion): the rows that hold the solution (touching ones included) must leave
/// no rigid motion free, as the multiplier methods require of their active sets.
void settle_active_set(const ConstrainedProblem& p, const StrategyOptions& o,
                       ConstraintSolution& s, bool check_rigid_motion) {
  s.active = touching_rows(p, o, s);
  const VecX gap = p.gap0 + p.gap_jacobian * s.u;
  const double touch = penetration_tolerance(o, p);
  std::vector<char> holding(p.num_gaps(), 0);
  for (int i = 0; i < p.num_gaps(); ++i) {
    if (!s.active[i]) s.contact_force[i] = 0.0;
    holding[i] = s.active[i] || gap[i] <= touch;
  }
  if (check_rigid_motion && s.status == SolveStatus::kConverged &&
      !holds_every_rigid_motion(p, holding, p.has_friction() ? &s.friction_state : nullptr)) {
    s.status = SolveStatus::kSingular;
    s.message = "the minimiser is not unique: with the rows that hold it the structure is "
                "free to move (a body pulled off its supports, or unsupported)";
  }
}


QpOutcome optimise(Ipopt::SmartPtr<QpTnlp> qp, const StrategyOptions& o, double tolerance) {
  QpOutcome out;
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  auto opt = app->Options();
  opt->SetStringValue("sb", "yes");
  opt->SetIntegerValue("print_level", 0);
  opt->SetNumericValue("tol", tolerance);
  opt->SetIntegerValue("max_iter", std::max(200, 20 * o.max_iterations));
  opt->SetStringValue("hessian_constant", "yes");
  opt->SetStringValue("jac_c_constant", "yes");
  opt->SetStringValue("jac_d_constant", "yes");
  opt->SetStringValue("mu_strategy", "adaptive");
  // Exact enforcement: no relaxation of the bounds.
  opt->SetNumericValue("bound_relax_factor", 0.0);
  // From an empty options stream: Initialize() would read ./ipopt.opt, so a file of that name
  // in the caller's working folder would change the method's settings behind its back.
  std::istringstream no_options;
  Ipopt::ApplicationReturnStatus st = app->Initialize(no_options);
  if (st != Ipopt::Solve_Succeeded) {
    out.message = "Ipopt initialisation failed";
    return out;
  }
  st = app->OptimizeTNLP(Ipopt::SmartPtr<Ipopt::TNLP>(qp));
  core::check_interrupt();
  out.status = map_status(st, out.message);
  out.iterations = Ipopt::IsValid(app->Statistics()) ? app->Statistics()->IterationCount() : 0;
  out.x = qp->x;
  out.lambda = qp->lambda;
  return out;
}

QpOutcome run_ipopt(const ConstrainedProblem& p, const RowSet& rows, const VecX& cost,
                    const StrategyOptions& o, double tolerance) {
  return optimise(new ContactQp(p, rows, cost), o, tolerance);
}

/// Forces from Ipopt's multipliers (its Lagrangian is f + gᵀλ: a row exerts −λ / |row|): the
/// gap rows' λ ≥ 0, the equality rows' μ, and λ_t = φ⁺ − φ⁻ from a Tresca row pair.
void extract_forces(const ConstrainedProblem& p, const RowSet& rows,
                    const std::vector<int>& friction_sign, const QpOutcome& qp,
                    ConstraintSolution& s) {
  s.u = qp.x.size() >= p.num_unknowns() ? VecX(qp.x.head(p.num_unknowns()))
                                        : VecX::Zero(p.num_unknowns());
  s.contact_force = VecX::Zero(p.num_gaps());
  s.eq_multiplier = VecX::Zero(p.num_equalities());
  if (p.has_friction()) s.tangent_force = VecX::Zero(p.num_gaps());
  if (qp.lambda.size() != static_cast<int>(rows.rows.size())) return;
  for (size_t r = 0; r < rows.rows.size(); ++r) {
    const KeptRow& k = rows.rows[r];
    const double force = -qp.lambda[static_cast<int>(r)] / k.norm;
    if (r < friction_sign.size() && friction_sign[r] == 2)  // a sticking equality: −T_iᵀ λ_t
      s.tangent_force[k.source] = -force;
    else if (r < friction_sign.size() && friction_sign[r] != 0)
      s.tangent_force[k.source] += friction_sign[r] * std::max(0.0, force);
    else if (k.equality)
      s.eq_multiplier[k.source] = force;
    else
      s.contact_force[k.source] = std::max(0.0, force);
  }
}

}  // namespace ipopt_detail

using namespace ipopt_detail;

namespace {

/// Frictionless: on the surface when it condenses and its set is confirmed, else Ipopt on the
/// whole KKT system (one factorisation per interior-point iteration). Returns the iterations.
/// Where K_T does not factorise even with every row regularising, the QP is not convex and
/// the whole system's interior point only wanders (a pin in a frictionless hole, free to turn
/// under compression: 1,000 iterations a solve, 362 s to fail): not applicable.
int solve_frictionless(const ConstrainedProblem& p, const RowSet& base, const StrategyOptions& o,
                       const SetRule& rule, bool& loose_first, ConstraintSolution& s) {
  ConstraintSolution surface;
  const bool condensed = solve_condensed_dual(p, base, o, rule, loose_first, surface);
  if (condensed && surface.status == SolveStatus::kConverged) {
    s = std::move(surface);
    return s.iterations;
  }
  add_solution_work(surface, s);
  if (!surface.not_applicable.empty()) {
    s.status = SolveStatus::kFailed;
    s.message = s.not_applicable = surface.not_applicable;
    return 0;
  }
  const QpOutcome qp = run_ipopt(p, base, VecX(), o, o.ipopt_tolerance);
  extract_forces(p, base, {}, qp, s);
  s.status = qp.status;
  s.message = qp.message;
  s.factorizations += qp.iterations;
  IterationRecord rec;
  rec.iteration = qp.iterations;
  rec.max_penetration = max_penetration(VecX(p.gap0 + p.gap_jacobian * s.u));
  s.history.push_back(rec);
  settle_active_set(p, o, s);
  return qp.iterations;
}

/// Coulomb: the fixed point of Tresca problems, on the surface when the rows condense; when its
/// sets are not confirmed there, again on the whole KKT system. Returns the iterations.
int solve_with_friction(const ConstrainedProblem& p, const RowMemory& memory, const RowSet& base,
                        const StrategyOptions& o, ConstraintSolution& s) {
  FrictionalSolver crossover(p, memory);  // one factor for every crossover of the fixed point
  int iterations = 0;
  for (const bool surface : {true, false}) {
    ConstraintSolution attempt;
    add_solution_work(s, attempt);
    VecX bound;
    bool exact = false, on_surface = false;
    attempt.message = solve_tresca_fixed_point(p, memory, o, base, crossover, surface, attempt,
                                               iterations, bound, exact, on_surface);
    exact = finish_friction(p, o, bound, exact, crossover, attempt);
    if (!on_surface) attempt.factorizations += iterations;  // one per KKT iteration
    s = std::move(attempt);
    if (!on_surface || exact) break;
  }
  return iterations;
}

}  // namespace

std::unique_ptr<ConstraintStrategy> IpoptStrategy::fallback() const {
  StrategyOptions o = options_;
  o.method = "lagrange";
  return ConstraintStrategy::create(o);
}

ConstraintSolution IpoptStrategy::solve_problem(const ConstrainedProblem& p,
                                                const RowMemory& memory) {
  ConstraintSolution s;
  const RowSet base = prepare_rows(p);
  if (!base.inconsistent.empty()) {
    s.status = SolveStatus::kFailed;
    s.message = "inconsistent constraints: " + base.inconsistent;
    return s;
  }
  const bool friction = p.has_friction();
  const int iterations = friction ? solve_with_friction(p, memory, base, options_, s)
                                  : solve_frictionless(p, base, options_, rule_, loose_first_, s);
  if (base.dropped_zero + base.dropped_duplicate > 0)
    s.message += (s.message.empty() ? "" : "; ") + std::string("dropped ") +
                 std::to_string(base.dropped_zero) + " zero and " +
                 std::to_string(base.dropped_duplicate) + " duplicate constraint rows";
  if (s.history.empty()) s.history.emplace_back();
  IterationRecord& last = s.history.back();
  last.active = count_active(s.active);
  last.entering = last.active;
  for (int i = 0; i < p.num_gaps() && friction; ++i) {
    last.stick += s.friction_state[i] == FrictionState::kStick;
    last.slip += s.friction_state[i] == FrictionState::kSlip;
  }
  s.iterations = iterations;
  return s;
}

}  // namespace c2d::constraints
