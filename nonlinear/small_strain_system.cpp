#include "nonlinear/structural_system.hpp"

namespace c2d::nonlinear {

VecX SmallStrainSystem::full(const VecX& u_free) const {
  VecX u = u_prescribed_;
  for (int dof = 0; dof < model_.dofs.num_dofs(); ++dof)
    if (const int eq = model_.dofs.equation(dof); eq >= 0) u[dof] = u_free[eq];
  return u;
}

bool SmallStrainSystem::step_predictor(const VecX& u0, VecX& load) {
  // rhs carries the whole prescribed lift K_fc u_c, so only the free part of u0 remains.
  load = rhs_ - k_ff_ * model_.dofs.restrict(u0);
  return true;
}

bool SmallStrainSystem::residual(const VecX& u_free, VecX& r) {
  r = k_ff_ * u_free - rhs_;
  return true;
}

}  // namespace c2d::nonlinear
