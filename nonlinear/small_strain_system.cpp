#include "nonlinear/structural_system.hpp"

namespace c2d::nonlinear {

VecX SmallStrainSystem::full(const VecX& u_free) const {
  return model_.dofs.with_free(u_prescribed_, u_free);
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
