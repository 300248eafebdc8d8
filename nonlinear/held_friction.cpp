#include "nonlinear/held_friction.hpp"

#include "constraints/strategy_common.hpp"

namespace c2d::nonlinear {

using namespace c2d::constraints;

HeldFriction::HeldFriction(const ConstrainedProblem& p, const VecX& c0,
                           const ConstraintSolution& sol, const VecX& u)
    : qp(p), s(sol) {
  const int m = p.num_gaps(), me = p.num_equalities();
  const SpMat tt = p.slip_jacobian.transpose();  // column i: the tangential row i
  VecX slip_force = sol.tangent_force;
  for (int i = 0; i < m; ++i)
    if (sol.active[i] && sol.friction_state[i] == FrictionState::kStick &&
        tt.col(i).nonZeros() > 0) {
      stick.push_back(i);
      slip_force[i] = 0.0;
    }
  fixed_force = -(tt * slip_force);
  const int ms = static_cast<int>(stick.size());
  std::vector<Triplet> t;
  for (int k = 0; k < ms; ++k)
    for (SpMat::InnerIterator it(tt, stick[k]); it; ++it)
      t.emplace_back(k, static_cast<int>(it.row()), -it.value());
  SpMat rows(ms, p.num_unknowns());
  rows.setFromTriplets(t.begin(), t.end());
  qp.eq_jacobian = stack_rows(p.eq_jacobian, rows);
  qp.eq_rhs.conservativeResize(me + ms);
  c = VecX(c0.size() + ms);
  c.head(c0.size()) = c0;
  s.eq_multiplier.conservativeResize(me + ms);
  const bool penalised = sol.eq_penalty.size() == me && sol.penalty.size() == m;
  if (penalised) s.eq_penalty.conservativeResize(me + ms);
  const VecX ratio = p.tangent_penalty_ratio.size() == m ? p.tangent_penalty_ratio : VecX::Ones(m);
  for (int k = 0; k < ms; ++k) {
    const int i = stick[k];
    qp.eq_rhs[me + k] = p.slip0[i];  // −T Δu − slip0 = −s
    double s_abs = p.slip0[i];
    for (SpMat::InnerIterator it(tt, i); it; ++it) s_abs -= it.value() * u[it.row()];
    c[c0.size() + k] = -s_abs;       // c − T u_f = −s at the free displacements u_f
    s.eq_multiplier[me + k] = sol.tangent_force[i];
    if (penalised) s.eq_penalty[me + k] = ratio[i] * sol.penalty[i];
  }
  s.tangent_force = VecX();  // the terms see the stick rows as equality rows
}

}  // namespace c2d::nonlinear
