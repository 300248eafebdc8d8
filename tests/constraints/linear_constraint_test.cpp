// Constraint rows: prescribed DOFs move to the right-hand side, free DOFs become columns.
#include <gtest/gtest.h>

#include "constraints/linear_constraint.hpp"

using namespace c2d;
using namespace c2d::constraints;

TEST(LinearConstraint, RowsEliminatePrescribedDofs) {
  // The seed's seven-spring chain constraint u2 - u6 = 0.20 (1-based) with u1 = 0 prescribed:
  // here DOFs 0..6, DOF 0 prescribed 0.5 to see it move to the right-hand side.
  core::DofMap dofs(7);
  dofs.constrain(0, 0.5);
  dofs.finalize();
  LinearConstraint c;
  c.terms = {{1, 1.0}, {5, -1.0}, {0, 2.0}};
  c.rhs = 0.20;
  const ConstraintRows rows = assemble_rows({c}, dofs);
  ASSERT_EQ(rows.jacobian.rows(), 1);
  ASSERT_EQ(rows.jacobian.cols(), 6);
  EXPECT_DOUBLE_EQ(rows.jacobian.coeff(0, 0), 1.0);   // DOF 1 -> equation 0
  EXPECT_DOUBLE_EQ(rows.jacobian.coeff(0, 4), -1.0);  // DOF 5 -> equation 4
  EXPECT_DOUBLE_EQ(rows.rhs[0], 0.20 - 2.0 * 0.5);
  const ConstraintRows half = assemble_rows({c}, dofs, 0.5);
  EXPECT_DOUBLE_EQ(half.rhs[0], 0.20 - 2.0 * 0.25);
}
