#include "core/dof_map.hpp"

#include <cmath>

namespace c2d::core {

bool DofMap::constrain(int dof, double value) {
  if (constrained_[dof]) {
    return std::abs(prescribed_[dof] - value) <= 1e-12 * std::max(1.0, std::abs(value));
  }
  constrained_[dof] = true;
  prescribed_[dof] = value;
  return true;
}

void DofMap::finalize() {
  equation_.assign(prescribed_.size(), -1);
  num_free_ = 0;
  for (size_t i = 0; i < prescribed_.size(); ++i)
    if (!constrained_[i]) equation_[i] = num_free_++;
}

VecX DofMap::expand(const VecX& free_values, double load_factor) const {
  VecX u(num_dofs());
  for (int i = 0; i < num_dofs(); ++i)
    u[i] = constrained_[i] ? load_factor * prescribed_[i] : free_values[equation_[i]];
  return u;
}

VecX DofMap::with_free(const VecX& full, const VecX& free_values) const {
  VecX u = full;
  for (int i = 0; i < num_dofs(); ++i)
    if (!constrained_[i]) u[i] = free_values[equation_[i]];
  return u;
}

VecX DofMap::restrict(const VecX& full) const {
  VecX r(num_free_);
  for (int i = 0; i < num_dofs(); ++i)
    if (!constrained_[i]) r[equation_[i]] = full[i];
  return r;
}

}  // namespace c2d::core
