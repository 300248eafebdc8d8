#include "nonlinear/contact_newton.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <set>

#include "constraints/saddle_point_solver.hpp"
#include "constraints/strategy_common.hpp"

namespace c2d::nonlinear {

using namespace c2d::constraints;

namespace {

/// The nonlinear equations of one outer iteration: the active rows fixed, their gaps linear in
/// the free displacements, g(u) = c + G u (the linearisation about the detection state).
///   penalty-type:  R(u)    = f_int(u) − λ f − G_Aᵀ (λ̂ − k g_A(u))             (CHOLMOD)
///   exact:         R(u, z) = [ f_int(u) − λ f − s G_Aᵀ z_A ;  −s g_A(u) ;  s z_I ]
/// with z = λ/s the multipliers scaled to the stiffness (s = mean diag K) and the inactive rows
/// kept as z = 0. The exact methods' Newton systems go to the SaddlePointSolver: a Cholesky of
/// K_T and the Schur complement of the active rows, or UMFPACK on the saddle point when K_T
/// alone is singular (a body held only by its contacts).
class ActiveSetSystem final : public NewtonSystem {
 public:
  ActiveSetSystem(FiniteStrainSystem& base, bool multipliers, const ConstrainedProblem& qp,
                  const VecX& c, std::vector<char> active, const VecX& k, const VecX& lambda_hat,
                  double scale)
      : base_(base), multipliers_(multipliers), g_(qp.gap_jacobian), gt_(g_.transpose()), c_(c),
        active_(std::move(active)), k_(k), lambda_hat_(lambda_hat), s_(scale),
        n_(static_cast<int>(g_.cols())), m_(static_cast<int>(g_.rows())) {
    if (multipliers_) {
      problem_.gap_jacobian = g_;
      problem_.gap0 = VecX::Zero(m_);
      problem_.load = VecX::Zero(n_);
      problem_.eq_jacobian = SpMat(0, n_);
      problem_.eq_rhs = VecX();
      saddle_ = std::make_unique<SaddlePointSolver>(problem_, s_);
    } else {
      VecX ka = VecX::Zero(m_);
      for (int i = 0; i < m_; ++i)
        if (active_[i]) ka[i] = k_[i];
      penalty_ = SpMat(gt_ * ka.asDiagonal() * g_);
    }
  }

  int size() const { return multipliers_ ? n_ + m_ : n_; }
  VecX pack(const VecX& u, const VecX& force) const {
    VecX x(size());
    x.head(n_) = u;
    if (multipliers_)
      for (int i = 0; i < m_; ++i) x[n_ + i] = active_[i] ? force[i] / s_ : 0.0;
    return x;
  }
  VecX gap(const VecX& x) const { return c_ + g_ * x.head(n_); }
  /// Row forces λ ≥ 0 (compressive) at x.
  VecX forces(const VecX& x, const VecX& gap) const {
    VecX f = VecX::Zero(m_);
    for (int i = 0; i < m_; ++i)
      if (active_[i]) f[i] = multipliers_ ? s_ * x[n_ + i] : lambda_hat_[i] - k_[i] * gap[i];
    return f;
  }

  bool residual(const VecX& x, VecX& r) override {
    VecX ru;
    if (!base_.residual(x.head(n_), ru)) return false;
    const VecX g = gap(x);
    r.resize(size());
    r.head(n_) = ru - gt_ * forces(x, g);
    if (multipliers_)
      for (int i = 0; i < m_; ++i) r[n_ + i] = active_[i] ? -s_ * g[i] : s_ * x[n_ + i];
    return true;
  }
  bool factorize_jacobian(const VecX& x) override {
    if (!base_.assemble(base_.full(x.head(n_)))) return false;
    if (multipliers_) {
      problem_.stiffness = base_.matrix();
      saddle_->stiffness_changed();
      const bool ok = saddle_->factorize(active_, true, analysed_) == SolveStatus::kConverged;
      analysed_ = true;
      return ok;
    }
    jacobian_ = base_.matrix() + penalty_;  // the solver keeps a reference for its residual check
    return spd_.factorize(jacobian_) == SolveStatus::kConverged;
  }
  bool solve(const VecX& b, VecX& x) override {
    return (multipliers_ ? saddle_->solve(b, x) : spd_.solve(b, x)) == SolveStatus::kConverged;
  }

 private:
  FiniteStrainSystem& base_;
  bool multipliers_;
  SpMat g_, gt_, penalty_, jacobian_;
  VecX c_;
  std::vector<char> active_;
  VecX k_, lambda_hat_;
  double s_;
  int n_, m_;
  ConstrainedProblem problem_;
  std::unique_ptr<SaddlePointSolver> saddle_;
  bool analysed_ = false;
  core::SpdSolver spd_{core::SpdSolver::Backend::kCholmod, false};
};

double inf_norm(const VecX& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

}  // namespace

ContactStepResult solve_contact_step(FiniteStrainSystem& system, const ContactSet& contact,
                                     ConstraintStrategy& strategy, const ContactStepInput& in) {
  ContactStepResult out;
  const core::DofMap& dofs = system.model().dofs;
  const bool exact = is_exact_method(strategy.name());
  const int slots = contact.num_slots();
  VecX u = in.u_free;
  ContactMemory previous = in.memory;
  previous.resize(slots, 0);
  std::set<ContactMemory> seen{previous};
  std::vector<double> force_by_slot(slots, 0.0);  ///< the last KINSOL solve's row forces
  double coordinate_scale = 0.0;                  ///< largest |coordinate|, for round-off
  for (const Vec2& xn : system.model().mesh.nodes)
    coordinate_scale = std::max(coordinate_scale, xn.cwiseAbs().maxCoeff());
  coordinate_scale += inf_norm(in.u_free) + contact.model_size();
  std::vector<GapRow> rows, state_rows;
  ConstraintSolution state;
  auto fail = [&](SolveStatus status, const std::string& message) {
    out.status = status;
    out.message = message;
    return out;
  };
  for (int outer = 1; outer <= in.max_outer; ++outer) {
    ContactIteration it;
    it.outer = outer;
    const std::string where = "outer iteration " + std::to_string(outer) + ": ";
    // 1. The problem linearised at the current state. The first iteration starts from the
    //    previous step's converged state and carries the prescribed increment as a lift.
    const VecX u_full = system.full(u);
    VecX load;
    if (outer == 1) {
      if (!system.step_predictor(in.u_prev_full, load))
        return fail(SolveStatus::kFailed, where + "an element is inverted");
    } else {
      VecX r;
      if (!system.residual(u, r) || !system.assemble(u_full))
        return fail(SolveStatus::kFailed, where + "an element is inverted");
      load = -r;
    }
    rows = contact.detect(u_full);
    ConstrainedProblem qp = contact.problem(system.matrix(), load, rows, u_full);
    const VecX c = qp.gap0;              // g(u_f) = c + G u_f
    qp.gap0 += qp.gap_jacobian * u;      // the gaps in terms of the step Δu
    const int m = qp.num_gaps();
    qp.initial_active.assign(m, 0);
    qp.initial_force = VecX::Zero(m);
    // Warm start: the rows closed at the last state, and rows touching or penetrating now.
    const double touch = touch_tolerance(qp);
    for (int i = 0; i < m; ++i) {
      qp.initial_active[i] = previous[rows[i].slot] || qp.gap0[i] <= touch;
      qp.initial_force[i] = force_by_slot[rows[i].slot];
    }

    // 2. The strategy on the linearised problem.
    const ConstraintSolution s = strategy.solve(qp);
    it.strategy_iterations = s.iterations;
    it.strategy_status = s.status;
    it.strategy_step = inf_norm(s.u);
    it.rows = m;
    ContactMemory next(slots, 0);
    for (int i = 0; i < m; ++i)
      if (s.active[i]) next[rows[i].slot] = 1;
    for (int k = 0; k < slots; ++k) {
      it.entering += next[k] && !previous[k];
      it.leaving += !next[k] && previous[k];
      it.active += next[k];
    }
    it.penalty = s.penalty.size() ? s.penalty.maxCoeff() : 0.0;
    if (s.status != SolveStatus::kConverged) {
      out.iterations.push_back(it);
      return fail(s.status, where + strategy.name() + ": " + s.message);
    }
    const bool same_set = outer > 1 && next == previous;
    if (outer > 1 && !same_set && !seen.insert(next).second) {
      out.iterations.push_back(it);
      return fail(SolveStatus::kCycling,
                  where + "the active set returned to an earlier set within the step");
    }

    // 3. KINSOL with the set fixed: from the strategy's step when the set changed; from the
    //    state itself (and, for exact methods, its own multipliers) when the strategy kept it.
    VecX k = s.penalty, lambda_hat = VecX::Zero(m), start_force = s.contact_force;
    if (!exact)
      for (int i = 0; i < m; ++i)
        if (s.active[i]) lambda_hat[i] = s.contact_force[i] + k[i] * s.gap[i];
    if (exact && same_set)
      for (int i = 0; i < m; ++i) start_force[i] = force_by_slot[rows[i].slot];
    // Without active rows the exact methods' system is K_T alone: CHOLMOD, not the saddle point.
    const bool multipliers = exact && std::find(s.active.begin(), s.active.end(), 1) != s.active.end();
    ActiveSetSystem sys(system, multipliers, qp, c, s.active, k, lambda_hat, saddle_point_scale(qp));
    VecX x = sys.pack(same_set ? u : VecX(u + s.u), start_force);
    NewtonOptions newton = in.newton;
    newton.residual_scale = std::max({newton.residual_scale, inf_norm(s.contact_force),
                                      system.reaction_scale(u + s.u), in.floor_scale});
    auto keep_state = [&]() {
      state = s;
      state_rows = rows;
      state.u = u;
      state.gap = sys.gap(x);
      state.contact_force = sys.forces(x, state.gap);
      state.max_penetration = max_penetration(state.gap);
      std::fill(force_by_slot.begin(), force_by_slot.end(), 0.0);
      for (int i = 0; i < m; ++i) force_by_slot[rows[i].slot] = state.contact_force[i];
      it.max_penetration = state.max_penetration;
      it.max_force = inf_norm(state.contact_force);
      ContactReport report;
      contact.report(rows, state, report);
      it.max_pressure = report.p_max;
    };
    // Converged when the strategy keeps the set and the state already satisfies the equations
    // with the rows detected at it: a node that slid, a normal that turned or a penalty the
    // strategy changed would show in this residual. A gap detected from absolute coordinates
    // carries their round-off, ε·|x|, which a row stiffness k turns into a force of k·ε·|x|:
    // with penalties 1e3 times the element stiffness that floor can exceed the tolerance, so it
    // bounds the test from below.
    if (same_set) {
      VecX r;
      double k_max = multipliers ? saddle_point_scale(qp) : 0.0;
      for (int i = 0; i < m; ++i)
        if (s.active[i]) k_max = std::max(k_max, k[i]);
      const double floor = 16.0 * std::numeric_limits<double>::epsilon() * coordinate_scale * k_max;
      if (sys.residual(x, r) &&
          inf_norm(r) <= std::max(newton.residual_tolerance * newton.residual_scale, floor)) {
        it.newton.status = SolveStatus::kConverged;
        it.newton.final_residual = inf_norm(r);
        it.newton.residual_norms = {it.newton.final_residual};
        keep_state();
        out.iterations.push_back(it);
        out.status = SolveStatus::kConverged;
        break;
      }
    }
    it.newton = solve_newton_with_fallback(sys, x, newton);
    out.newton.iterations += it.newton.iterations;
    out.newton.residual_norms.insert(out.newton.residual_norms.end(),
                                     it.newton.residual_norms.begin(),
                                     it.newton.residual_norms.end());
    out.newton.final_residual = it.newton.final_residual;
    out.newton.last_step = it.newton.last_step;
    if (it.newton.status != SolveStatus::kConverged) {
      out.iterations.push_back(it);
      return fail(it.newton.status, where + "Newton with the active set fixed: " +
                                        it.newton.message);
    }
    u = x.head(dofs.num_free());
    keep_state();
    out.iterations.push_back(it);
    previous = next;
  }
  if (out.status != SolveStatus::kConverged)
    return fail(SolveStatus::kMaxIterations,
                "active set or geometry still changing after " + std::to_string(in.max_outer) +
                    " outer iterations");
  out.newton.status = SolveStatus::kConverged;
  out.u_free = u;
  out.memory = previous;
  // The rows and forces of the KINSOL solve that produced the state (the strategy confirmed
  // their linearisation at it).
  out.rows = std::move(state_rows);
  out.state = std::move(state);
  return out;
}

void store_contact_results(const ContactReport& report, int nn, core::Results& r) {
  r.globals["contact_pressure_max"] = report.p_max;
  r.globals["contact_length"] = report.length;
  r.globals["contact_force"] = report.total_force;
  r.globals["contact_penetration"] = report.max_penetration;
  VecX gap = VecX::Zero(nn), pressure = VecX::Zero(nn), force = VecX::Zero(nn);
  for (const auto& cn : report.nodes) {
    gap[cn.node] = cn.gap;
    pressure[cn.node] = cn.pressure;
    force[cn.node] = cn.force;
  }
  r.point_fields["contact_gap"] = gap;
  r.point_fields["contact_pressure"] = pressure;
  r.point_fields["contact_force"] = force;
}

}  // namespace c2d::nonlinear
