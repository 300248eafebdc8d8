// A constraint expressed once, as a row of a sparse Jacobian, so every enforcement backend can
// consume it: equality  Σ a_j u_j = b  or inequality (gap)  Σ a_j u_j + g0 >= 0.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/dof_map.hpp"
#include "core/types.hpp"

namespace c2d::constraints {

struct LinearConstraint {
  enum class Kind { kEquality, kInequality };
  Kind kind = Kind::kEquality;
  std::vector<std::pair<int, double>> terms;  ///< (global DOF, coefficient a_j)
  double rhs = 0.0;                           ///< b (equality) or -g0 (inequality)
  std::string label;                          ///< for reports, e.g. "slave node 12"
};

/// Rows of constraints restricted to the free DOFs of a DofMap: A u_f (op) b - A_c u_c.
struct ConstraintRows {
  SpMat jacobian;  ///< m x num_free
  VecX rhs;        ///< m, with the prescribed DOFs moved to the right-hand side
};

/// Builds the rows; `load_factor` scales the prescribed values (as DofMap::expand does).
ConstraintRows assemble_rows(const std::vector<LinearConstraint>& constraints,
                             const core::DofMap& dofs, double load_factor = 1.0);

}  // namespace c2d::constraints
