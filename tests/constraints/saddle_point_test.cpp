// SaddlePointSolver: the Schur-complement path (CHOLMOD on K, or on K_ρ for a floating body) and the LU path (UMFPACK on the
// whole saddle point) solve the same systems; redundant rows are singular on both.
#include <gtest/gtest.h>

#include <random>

#include "constraints/saddle_point_solver.hpp"
#include "constraints/strategy_common.hpp"

using namespace c2d;
using namespace c2d::constraints;

namespace {

// A spring chain (SPD, n unknowns, grounded at the first) with `m` random gap rows of 3 entries
// and one equality row.
ConstrainedProblem chain(int n, int m, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> col(0, n - 1);
  ConstrainedProblem p;
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, i == 0 ? 3.0 : 2.0);
    if (i + 1 < n) t.emplace_back(i, i + 1, -1.0), t.emplace_back(i + 1, i, -1.0);
  }
  p.stiffness = SpMat(n, n);
  p.stiffness.setFromTriplets(t.begin(), t.end());
  p.load = VecX::NullaryExpr(n, [&] { return u(rng); });
  t.clear();
  for (int r = 0; r < m; ++r)
    for (int k = 0; k < 3; ++k) t.emplace_back(r, col(rng), u(rng));
  p.gap_jacobian = SpMat(m, n);
  p.gap_jacobian.setFromTriplets(t.begin(), t.end());
  p.gap0 = VecX::NullaryExpr(m, [&] { return u(rng); });
  p.eq_jacobian = SpMat(1, n);
  p.eq_jacobian.insert(0, n / 2) = 1.0;
  p.eq_rhs = VecX::Constant(1, 0.25);
  return p;
}

/// Solves the factorised saddle point for `active` and compares with Eigen's dense LU of the
/// assembled matrix (1e-10 relative to the solution's largest entry).
void expect_dense_solution(SaddlePointSolver& solver, const ConstrainedProblem& p,
                           const std::vector<char>& active, double s, bool all_rows) {
  const VecX b = saddle_point_rhs(p, active, s, all_rows);
  VecX x;
  ASSERT_EQ(solver.solve(b, x), SolveStatus::kConverged);
  const Eigen::MatrixXd dense(saddle_point_matrix(p, active, s, all_rows));
  const VecX ref = dense.fullPivLu().solve(b);
  EXPECT_LT((x - ref).cwiseAbs().maxCoeff(), 1e-10 * ref.cwiseAbs().maxCoeff()) << all_rows;
}

}  // namespace

TEST(SaddlePointSolver, SchurAndLuAgreeForEveryLayout) {
  // Reference: Eigen's dense LU of the assembled saddle-point matrix. Tolerance 1e-10 relative:
  // the chain's condition number is ~n² = 1e4.
  const ConstrainedProblem p = chain(100, 12, 7);
  const double s = saddle_point_scale(p);
  std::vector<char> active(12, 0);
  for (int i = 0; i < 12; i += 2) active[i] = 1;
  for (bool all_rows : {false, true}) {
    SaddlePointSolver solver(p, s);
    ASSERT_EQ(solver.factorize(active, all_rows, false), SolveStatus::kConverged);
    EXPECT_TRUE(solver.uses_schur());
    expect_dense_solution(solver, p, active, s, all_rows);
    // A second active set reuses K's factor and the W columns already computed.
    std::vector<char> next = active;
    next[1] = 1;
    next[0] = 0;
    ASSERT_EQ(solver.factorize(next, all_rows, all_rows), SolveStatus::kConverged);
    expect_dense_solution(solver, p, next, s, all_rows);
    EXPECT_EQ(solver.report().numeric_factorizations, 1);  // one Cholesky for both sets
  }
}

TEST(SaddlePointSolver, FloatingBodyIsRegularisedByItsOwnRows) {
  // Without the ground spring K has a rigid mode (K 1 = 0); the rows remove it. The Schur path
  // factorises K_ρ = K + C_Rᵀ ρ C_R once and solves every active set and layout with it
  // (reference: dense LU of the unregularised saddle point, 1e-9 relative).
  ConstrainedProblem p = chain(80, 10, 11);
  p.stiffness.coeffRef(0, 0) = 1.0;
  p.stiffness.coeffRef(79, 79) = 1.0;  // both ends free: K 1 = 0
  ASSERT_LT((p.stiffness * VecX::Ones(80)).norm(), 1e-14);
  const double s = saddle_point_scale(p);
  for (bool all_rows : {false, true}) {
    SaddlePointSolver solver(p, s);
    std::vector<char> active(10, 0);
    for (int step = 0; step < 4; ++step) {
      active[(3 * step) % 10] = 1;
      if (step == 3) active[0] = 0;
      ASSERT_EQ(solver.factorize(active, all_rows, step > 0 && all_rows), SolveStatus::kConverged);
      EXPECT_TRUE(solver.uses_schur());
      expect_dense_solution(solver, p, active, s, all_rows);
    }
      // One numeric factorisation (K_ρ's) for four active sets.
    EXPECT_EQ(solver.report().numeric_factorizations, 1);
  }
}

TEST(SaddlePointSolver, ARigidModeNoRowReachesIsSingular) {
  // The only row, u_10 − u_20 = 0.25, is orthogonal to the rigid mode: K_ρ stays singular, the
  // LU path takes the saddle point and reports it singular rather than returning a number.
  ConstrainedProblem p = chain(40, 0, 3);
  p.stiffness.coeffRef(0, 0) = 1.0;
  p.stiffness.coeffRef(39, 39) = 1.0;
  p.eq_jacobian = SpMat(1, 40);
  p.eq_jacobian.insert(0, 10) = 1.0;
  p.eq_jacobian.insert(0, 20) = -1.0;
  SaddlePointSolver solver(p, saddle_point_scale(p));
  EXPECT_NE(solver.factorize({}, false, false), SolveStatus::kConverged);
  EXPECT_FALSE(solver.uses_schur());
}

TEST(SaddlePointSolver, RedundantRowsAreSingular) {
  // The same gap row twice: the Schur complement is singular (a zero pivot, ratio < 1e-13).
  ConstrainedProblem p = chain(30, 2, 5);
  SpMat g(2, 30);
  g.insert(0, 10) = 1.0;
  g.insert(1, 10) = 1.0;
  p.gap_jacobian = g;
  SaddlePointSolver solver(p, saddle_point_scale(p));
  EXPECT_EQ(solver.factorize({1, 1}, false, false), SolveStatus::kSingular);
  EXPECT_NE(solver.report().message.find("linearly dependent"), std::string::npos);
}
