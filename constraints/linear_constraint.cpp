#include "constraints/linear_constraint.hpp"

namespace c2d::constraints {

ConstraintRows assemble_rows(const std::vector<LinearConstraint>& constraints,
                             const core::DofMap& dofs, double load_factor) {
  ConstraintRows rows;
  const int m = static_cast<int>(constraints.size());
  std::vector<Triplet> triplets;
  rows.rhs.resize(m);
  for (int i = 0; i < m; ++i) {
    double b = constraints[i].rhs;
    for (const auto& [dof, a] : constraints[i].terms) {
      const int eq = dofs.equation(dof);
      if (eq >= 0)
        triplets.emplace_back(i, eq, a);
      else
        b -= a * load_factor * dofs.prescribed(dof);
    }
    rows.rhs[i] = b;
  }
  rows.jacobian.resize(m, dofs.num_free());
  rows.jacobian.setFromTriplets(triplets.begin(), triplets.end());
  return rows;
}

}  // namespace c2d::constraints
