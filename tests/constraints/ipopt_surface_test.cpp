// ipopt on the problem condensed onto its rows (constraints/methods/ipopt_dual.cpp): the dual QP
// on one factorisation of K, against closed-form solutions and lagrange's.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "constraints/constraint_strategy.hpp"
#include "constraints/friction_laws/coulomb.hpp"

using namespace c2d;
using namespace c2d::constraints;

namespace {

SpMat sparse(const Eigen::MatrixXd& d) { return d.sparseView(); }

ConstraintSolution solve(const std::string& method, const ConstrainedProblem& p) {
  StrategyOptions o;
  o.method = method;
  return ConstraintStrategy::create(o)->solve(p);
}

// Three nodes joined by two springs k, held by nothing but two stops: x1 ≥ −0.1 and
// x3 ≥ −0.3, pushed by P towards them at node 2. K is singular (the chain's translation).
// Node 1 touches: x1 = −0.1, x2 = x3 = −0.1 − P/k, the stop carries P, node 3 stays open.
ConstrainedProblem floating_chain(double push) {
  const double k = 1000.0;
  Eigen::MatrixXd kk(3, 3);
  kk << k, -k, 0, -k, 2 * k, -k, 0, -k, k;
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(2, 3);
  g(0, 0) = 1;
  g(1, 2) = 1;
  ConstrainedProblem p;
  p.stiffness = sparse(kk);
  p.load = Eigen::Vector3d(0, -push, 0);
  p.eq_jacobian = SpMat(0, 3);
  p.eq_rhs = VecX();
  p.gap_jacobian = sparse(g);
  p.gap0 = Eigen::Vector2d(0.1, 0.3);
  return p;
}

// One node (x tangential, y normal) on a spring kx to the ground and, vertically, two springs
// 2 ky in series through an unloaded interior node m (so the rows leave an interior unknown to
// condense: ky overall); its gap g = 0.01 + y to a rigid floor, loaded by (fx, −P), Coulomb
// friction μ = 0.5. In contact y = −0.01, the normal force λ = P − ky·0.01; it sticks (x = 0,
// λ_t = fx) while |fx| ≤ μ λ, else it slips with λ_t = μ λ sign(fx) and x = (fx − λ_t) / kx.
ConstrainedProblem node_on_floor(double fx) {
  const double kx = 200.0, k2 = 600.0, push = 10.0;
  Eigen::Matrix3d k;  // unknowns x, y, m
  k << kx, 0, 0, 0, k2, -k2, 0, -k2, 2 * k2;
  ConstrainedProblem p;
  p.stiffness = sparse(k);
  p.load = Eigen::Vector3d(fx, -push, 0);
  p.eq_jacobian = SpMat(0, 3);
  p.eq_rhs = VecX();
  p.gap_jacobian = sparse(Eigen::RowVector3d(0, 1, 0));
  p.gap0 = VecX::Constant(1, 0.01);
  p.slip_jacobian = sparse(Eigen::RowVector3d(1, 0, 0));
  p.slip0 = VecX::Zero(1);
  p.friction_law = {std::make_shared<Coulomb>(0.5)};
  p.gap_area = VecX::Ones(1);
  p.tangent_penalty_ratio = VecX::Ones(1);
  return p;
}

}  // namespace

TEST(IpoptSurface, HoldsABodyHeldOnlyByContactWithOneFactorisation) {
  // The chain's translation is held by the stops alone: the dual's equilibrium equation (the
  // rows' forces balance P) carries it, and the translation comes back as its multiplier.
  const double push = 50.0, k = 1000.0;
  const ConstraintSolution s = solve("ipopt", floating_chain(push));
  ASSERT_EQ(s.status, SolveStatus::kConverged) << s.message;
  EXPECT_EQ(s.factorizations, 1);
  EXPECT_NEAR(s.u[0], -0.1, 1e-12);
  EXPECT_NEAR(s.u[1], -0.1 - push / k, 1e-12);
  EXPECT_NEAR(s.u[2], -0.1 - push / k, 1e-12);
  EXPECT_NEAR(s.contact_force[0], push, 1e-9 * push);
  EXPECT_EQ(s.contact_force[1], 0.0);
  EXPECT_EQ(s.active[0], 1);
  EXPECT_EQ(s.active[1], 0);
}

TEST(IpoptSurface, NamesABodyPulledOffItsOnlySupports) {
  // Pulled away from both stops nothing balances the load: no answer, and a named status.
  const ConstraintSolution s = solve("ipopt", floating_chain(-50.0));
  EXPECT_NE(s.status, SolveStatus::kConverged) << s.message;
  EXPECT_TRUE(s.u.allFinite());
}

TEST(IpoptSurface, MatchesLagrangeOnASupportedChainWithOneFactorisation) {
  // Seven springs on a support with a multipoint constraint, pressed on a stop at node 7
  // (equality rows free in the dual, the gap row bounded); lagrange's exact solution to 1e-10.
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(7, 7);
  for (int i = 0; i < 7; ++i) k(i, i) = (i == 0 || i == 6) ? 100 : 200;
  for (int i = 0; i < 6; ++i) k(i, i + 1) = k(i + 1, i) = -100;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2, 7), g = Eigen::MatrixXd::Zero(1, 7);
  a(0, 0) = 1, a(1, 1) = 1, a(1, 5) = -1, g(0, 6) = -1;
  ConstrainedProblem p;
  p.stiffness = sparse(k);
  p.load = VecX::LinSpaced(7, 1, 7);
  p.eq_jacobian = sparse(a);
  p.eq_rhs = Eigen::Vector2d(0, 0.20);
  p.gap_jacobian = sparse(g);
  p.gap0 = VecX::Constant(1, 0.1);
  const ConstraintSolution lag = solve("lagrange", p), ip = solve("ipopt", p);
  ASSERT_EQ(lag.status, SolveStatus::kConverged) << lag.message;
  ASSERT_EQ(ip.status, SolveStatus::kConverged) << ip.message;
  EXPECT_EQ(ip.factorizations, 1);
  EXPECT_LT((ip.u - lag.u).cwiseAbs().maxCoeff(), 1e-10 * lag.u.cwiseAbs().maxCoeff());
  EXPECT_NEAR(ip.contact_force[0], lag.contact_force[0], 1e-10 * lag.contact_force[0]);
  EXPECT_LT((ip.eq_multiplier - lag.eq_multiplier).cwiseAbs().maxCoeff(),
            1e-10 * lag.eq_multiplier.cwiseAbs().maxCoeff());
}

TEST(IpoptSurface, CoulombStickAndSlipOfANodeOnAFloor) {
  // The Tresca problems of the fixed point differ in their bounds only: one factorisation for
  // the dual and one for the crossover that solves its sets exactly, whatever the rounds.
  const double kx = 200.0, lambda = 10.0 - 300.0 * 0.01, mu = 0.5;
  for (const double fx : {1.0, -3.0, 5.0, -8.0}) {
    const ConstraintSolution s = solve("ipopt", node_on_floor(fx));
    ASSERT_EQ(s.status, SolveStatus::kConverged) << fx << ": " << s.message;
    EXPECT_LE(s.factorizations, 2) << fx;
    EXPECT_NEAR(s.u[1], -0.01, 1e-12) << fx;
    EXPECT_NEAR(s.contact_force[0], lambda, 1e-9 * lambda) << fx;
    const bool sticks = std::abs(fx) <= mu * lambda;
    const double lt = sticks ? fx : std::copysign(mu * lambda, fx);
    EXPECT_NEAR(s.tangent_force[0], lt, 1e-9 * lambda) << fx;
    EXPECT_NEAR(s.u[0], (fx - lt) / kx, 1e-12) << fx;
    EXPECT_EQ(s.friction_state[0], sticks ? FrictionState::kStick : FrictionState::kSlip) << fx;
  }
}

// Ipopt's Initialize() reads ./ipopt.opt: a file of that name in the caller's working folder
// (here one that allows no iteration) must not change the method. The chain's answer as above.
TEST(IpoptSurface, IgnoresAnOptionsFileInTheWorkingFolder) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("c2d-ipopt-opt-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "ipopt.opt") << "max_iter 0\nmu_oracle loqo\n";
  const std::filesystem::path before = std::filesystem::current_path();
  std::filesystem::current_path(dir);  // this test's own process (one test a process under CTest)
  const ConstraintSolution s = solve("ipopt", floating_chain(50.0));
  std::filesystem::current_path(before);
  std::filesystem::remove_all(dir);
  ASSERT_EQ(s.status, SolveStatus::kConverged) << s.message;
  EXPECT_NEAR(s.u[0], -0.1, 1e-12);
  EXPECT_NEAR(s.u[1], -0.1 - 50.0 / 1000.0, 1e-12);
}
