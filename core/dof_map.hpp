// Numbering of the free degrees of freedom after Dirichlet elimination.
#pragma once

#include <vector>

#include "core/types.hpp"

namespace c2d::core {

/// Global DOF 2*node + component (0 = x, 1 = y). Constrained DOFs carry a prescribed value and
/// are eliminated: they get no equation; free DOFs are numbered 0..num_free()-1 in node order.
class DofMap {
 public:
  explicit DofMap(int num_dofs = 0) : prescribed_(num_dofs, 0.0), constrained_(num_dofs, false) {}

  /// Prescribes u[dof] = value. A second prescription of the same DOF must agree.
  /// Returns false on a conflicting value.
  bool constrain(int dof, double value);
  /// Numbers the free DOFs; call after the last constrain().
  void finalize();

  int num_dofs() const { return static_cast<int>(prescribed_.size()); }
  int num_free() const { return num_free_; }
  int num_constrained() const { return num_dofs() - num_free_; }
  bool is_constrained(int dof) const { return constrained_[dof]; }
  /// Equation number of a free DOF, -1 for a constrained one.
  int equation(int dof) const { return equation_[dof]; }
  double prescribed(int dof) const { return prescribed_[dof]; }

  /// Full vector from free values plus prescribed values scaled by `load_factor`.
  VecX expand(const VecX& free_values, double load_factor = 1.0) const;
  /// `full` with its free entries replaced by `free_values` (the constrained ones kept).
  VecX with_free(const VecX& full, const VecX& free_values) const;
  /// Free part of a full vector.
  VecX restrict(const VecX& full) const;

 private:
  std::vector<double> prescribed_;
  std::vector<bool> constrained_;
  std::vector<int> equation_;
  int num_free_ = 0;
};

}  // namespace c2d::core
