#include "nonlinear/contact_newton.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <set>
#include <utility>


namespace c2d::nonlinear {

using namespace c2d::constraints;

namespace {

/// The nonlinear equations of one outer iteration: the active rows fixed, their gaps linear in
/// the free displacements, g(u) = c + G u (the linearisation about the detection state), and
/// the strategy's terms for that set (its forces and stiffness, or its multipliers):
///   R(x) = [ f_int(u) − λ f − Gᵀ λ(x) ;  r_terms(x) ],   x = [u; the terms' unknowns].
class ActiveSetSystem final : public NewtonSystem {
 public:
  ActiveSetSystem(FiniteStrainSystem& base, const SpMat& g, const VecX& c,
                  std::unique_ptr<ActiveSetTerms> terms)
      : base_(base), g_(g), gt_(g_.transpose()), c_(c), terms_(std::move(terms)),
        n_(static_cast<int>(g_.cols())) {}

  int size() const { return n_ + terms_->extra_unknowns(); }
  VecX pack(const VecX& u, const VecX& force) const {
    VecX x(size());
    x.head(n_) = u;
    terms_->pack_forces(force, x.tail(size() - n_));
    return x;
  }
  VecX gap(const VecX& x) const { return c_ + g_ * x.head(n_); }
  /// Row forces λ ≥ 0 (compressive) at x.
  VecX forces(const VecX& x, const VecX& gap) const {
    return terms_->forces(gap, x.tail(size() - n_));
  }
  double row_stiffness() const { return terms_->row_stiffness(); }

  bool residual(const VecX& x, VecX& r) override {
    VecX ru;
    if (!base_.residual(x.head(n_), ru)) return false;
    const VecX g = gap(x);
    r.resize(size());
    r.head(n_) = ru - gt_ * forces(x, g);
    terms_->extra_residual(g, x.tail(size() - n_), r.tail(size() - n_));
    return true;
  }
  bool factorize_jacobian(const VecX& x) override {
    return base_.assemble(base_.full(x.head(n_))) && terms_->factorize(base_.matrix());
  }
  bool solve(const VecX& b, VecX& x) override { return terms_->solve(b, x); }

 private:
  FiniteStrainSystem& base_;
  SpMat g_, gt_;
  VecX c_;
  std::unique_ptr<ActiveSetTerms> terms_;
  int n_;
};

double inf_norm(const VecX& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

}  // namespace

ContactStepResult solve_contact_step(FiniteStrainSystem& system, const ContactSet& contact,
                                     ConstraintStrategy& strategy, const ContactStepInput& in) {
  ContactStepResult out;
  const core::DofMap& dofs = system.model().dofs;
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
    //    (Terms whose forces follow from u, the penalty-type ones, ignore the start forces.)
    VecX start_force = s.contact_force;
    if (same_set)
      for (int i = 0; i < m; ++i) start_force[i] = force_by_slot[rows[i].slot];
    ActiveSetSystem sys(system, qp.gap_jacobian, c, strategy.active_set_terms(qp, s));
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
      const double floor =
          16.0 * std::numeric_limits<double>::epsilon() * coordinate_scale * sys.row_stiffness();
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
