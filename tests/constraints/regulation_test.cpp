// The seed's two regulation examples (chapter 3.2) solved through the constraint layer, with
// every backend: supports and multipoint constraints are rows A u = b, not eliminations.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "constraints/active_set_tracker.hpp"
#include "constraints/constraint_strategy.hpp"
#include "constraints/method_registry.hpp"

using namespace c2d;
using namespace c2d::constraints;

namespace {

SpMat sparse(const Eigen::MatrixXd& d) { return d.sparseView(); }

// Two bars in series, node 2 between them, F = 200 kN at node 2, u1 = u3 = 0 (N, mm).
ConstrainedProblem two_bars() {
  const double k1 = 70000.0 * 2400.0 / 300.0, k2 = 200000.0 * 600.0 / 400.0;
  Eigen::MatrixXd k(3, 3);
  k << k1, -k1, 0, -k1, k1 + k2, -k2, 0, -k2, k2;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2, 3);
  a(0, 0) = 1;
  a(1, 2) = 1;
  ConstrainedProblem p;
  p.stiffness = sparse(k);
  p.load = Eigen::Vector3d(0, 200000.0, 0);
  p.eq_jacobian = sparse(a);
  p.eq_rhs = VecX::Zero(2);
  p.gap_jacobian = SpMat(0, 3);
  p.gap0 = VecX();
  p.model_size = 700.0;
  return p;
}

// Seven springs: k11 = k77 = 100, k22..k66 = 200, k_i,i+1 = -100, f_i = i, u1 = 0, u2 - u6 = 0.2.
ConstrainedProblem spring_chain() {
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(7, 7);
  for (int i = 0; i < 7; ++i) k(i, i) = (i == 0 || i == 6) ? 100 : 200;
  for (int i = 0; i < 6; ++i) k(i, i + 1) = k(i + 1, i) = -100;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2, 7);
  a(0, 0) = 1;
  a(1, 1) = 1;
  a(1, 5) = -1;
  ConstrainedProblem p;
  p.stiffness = sparse(k);
  p.load = VecX::LinSpaced(7, 1, 7);
  p.eq_jacobian = sparse(a);
  p.eq_rhs = Eigen::Vector2d(0, 0.20);
  p.gap_jacobian = SpMat(0, 7);
  p.gap0 = VecX();
  p.model_size = 1.0;
  return p;
}

// The chain with a stop u7 <= 0.1 (gap 0.1 − u7 >= 0): free u7 would be 0.14, so it closes.
ConstrainedProblem chain_against_stop() {
  ConstrainedProblem p = spring_chain();
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(1, 7);
  g(0, 6) = -1;
  p.gap_jacobian = sparse(g);
  p.gap0 = VecX::Constant(1, 0.1);
  return p;
}

// Options under which every method must reach the seed's 5 significant digits: the penalty-type
// methods get a tolerance or stiffness fine enough for that (their error is O(1/k)).
StrategyOptions options_for(const std::string& method) {
  StrategyOptions o;
  o.method = method;
  o.tolerance = 1e-10;
  o.penalty_factor = 1e9;
  o.max_penalty_factor = 1e12;
  return o;
}

class EveryMethod : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(EveryMethod, TwoBarsMiddleDisplacement) {
  const auto strategy = ConstraintStrategy::create(options_for(GetParam()));
  const ConstraintSolution s = strategy->solve(two_bars());
  ASSERT_EQ(s.status, SolveStatus::kConverged) << s.message;
  // Reference: u2 = F / (k1 + k2) = 0.23256 mm (seed, chapter 3.2).
  EXPECT_NEAR(s.u[1], 0.23256, 5e-6);
  EXPECT_NEAR(s.u[1], 200000.0 / 860000.0, 1e-9 * 0.23256 + (GetParam() == "penalty" ? 1e-6 : 0));
  // Support reactions: -k1 u2 and -k2 u2, summing to -F.
  EXPECT_NEAR(s.eq_multiplier[0] + s.eq_multiplier[1], -200000.0, 1e-3);
}

TEST_P(EveryMethod, SpringChainDisplacementsAndMultipliers) {
  const auto strategy = ConstraintStrategy::create(options_for(GetParam()));
  const ConstraintSolution s = strategy->solve(spring_chain());
  ASSERT_EQ(s.status, SolveStatus::kConverged) << s.message;
  const double expected[7] = {0, 0.27, 0.275, 0.25, 0.185, 0.07, 0.14};
  for (int i = 0; i < 7; ++i) EXPECT_NEAR(s.u[i], expected[i], 1e-7) << "u" << i + 1;
  // The seed's multipliers have magnitudes 28 (support) and 24.5 (u2 - u6 = 0.2).
  EXPECT_NEAR(s.eq_multiplier[0], -28.0, 1e-4);
  EXPECT_NEAR(s.eq_multiplier[1], 24.5, 1e-4);
}

TEST_P(EveryMethod, ChainAgainstAStopIsExactWithTheKnownActiveSet) {
  // The stop closes: the solution is the equality solution with u7 = 0.1 added, solved here
  // densely.
  ConstrainedProblem p = chain_against_stop();
  const Eigen::MatrixXd g(p.gap_jacobian);
  Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(10, 10);
  kkt.topLeftCorner(7, 7) = Eigen::MatrixXd(p.stiffness);
  Eigen::MatrixXd rows(3, 7);
  rows << Eigen::MatrixXd(p.eq_jacobian), g;
  kkt.topRightCorner(7, 3) = rows.transpose();
  kkt.bottomLeftCorner(3, 7) = rows;
  VecX rhs(10);
  rhs << p.load, p.eq_rhs, -0.1;
  const VecX ref = kkt.fullPivLu().solve(rhs);
  const auto strategy = ConstraintStrategy::create(options_for(GetParam()));
  const ConstraintSolution s = strategy->solve(p);
  ASSERT_EQ(s.status, SolveStatus::kConverged) << s.message;
  for (int i = 0; i < 7; ++i) EXPECT_NEAR(s.u[i], ref[i], 1e-7) << "u" << i + 1;
  EXPECT_NEAR(s.contact_force[0], -ref[9], 1e-5);  // dense KKT sign: K u + Gᵀ ν = f
  EXPECT_GT(s.contact_force[0], 0.0);
  EXPECT_EQ(s.active[0], 1);
}

TEST_P(EveryMethod, NewtonTermsHoldTheSolutionOfTheirActiveSet) {
  // The chain on a ground spring (no equality rows, as in a load step) against the stop: at the
  // strategy's own solution the Newton residual of its terms, R = K u − f − Gᵀ λ(u) with the
  // terms' own equations, vanishes and one Newton step from there stays there (to 1e-9
  // relative, plus the round-off floor 64 ε k |u| of a row of stiffness k).
  ConstrainedProblem p = spring_chain();
  p.stiffness.coeffRef(0, 0) += 100.0;
  p.eq_jacobian = SpMat(0, 7);
  p.eq_rhs = VecX();
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(1, 7);
  g(0, 6) = -1;
  p.gap_jacobian = sparse(g);
  p.gap0 = VecX::Constant(1, 0.1);
  // Default options: with the default penalties the round-off floor of the residual,
  // ε k |u| per row, stays far below the tolerance.
  StrategyOptions o;
  o.method = GetParam();
  const auto strategy = ConstraintStrategy::create(o);
  EXPECT_EQ(strategy->exact(), is_exact_method(GetParam()));
  const ConstraintSolution s = strategy->solve(p);
  ASSERT_EQ(s.status, SolveStatus::kConverged) << s.message;
  ASSERT_EQ(s.active[0], 1);
  const auto terms = strategy->active_set_terms(p, s);
  const int n = 7, size = n + terms->extra_unknowns();
  VecX x(size);
  x.head(n) = s.u;
  terms->pack_forces(s.contact_force, x.tail(size - n));
  const VecX gap = p.gap0 + p.gap_jacobian * s.u;
  const VecX force = terms->forces(gap, x.tail(size - n));
  EXPECT_NEAR(force[0], s.contact_force[0], 1e-9 * s.contact_force[0]);
  VecX r(size);
  r.head(n) = p.stiffness * s.u - p.load - SpMat(p.gap_jacobian.transpose()) * force;
  terms->extra_residual(gap, x.tail(size - n), r.tail(size - n));
  const double floor = 64 * std::numeric_limits<double>::epsilon() * terms->row_stiffness() *
                      s.u.cwiseAbs().maxCoeff();
  EXPECT_LT(r.cwiseAbs().maxCoeff(), 1e-9 * p.load.cwiseAbs().maxCoeff() + floor);
  ASSERT_TRUE(terms->factorize(p.stiffness));
  VecX dx;
  ASSERT_TRUE(terms->solve(-r, dx));
  EXPECT_LT(dx.head(n).cwiseAbs().maxCoeff(), 1e-9 * s.u.cwiseAbs().maxCoeff());
  EXPECT_GT(terms->row_stiffness(), 0.0);
}

// Every registered method runs the shared checks.
INSTANTIATE_TEST_SUITE_P(Constraints, EveryMethod, ::testing::ValuesIn(method_names()));

TEST(MethodRegistry, NamesAreUniqueAndEachEntryMakesItsOwnMethod) {
  std::set<std::string> seen;
  for (const MethodInfo& m : method_registry()) {
    EXPECT_TRUE(seen.insert(m.name).second) << m.name;
    EXPECT_FALSE(m.summary.empty()) << m.name;
    StrategyOptions o;
    o.method = m.name;
    const auto strategy = ConstraintStrategy::create(o);
    EXPECT_EQ(strategy->name(), m.name);
    EXPECT_EQ(strategy->exact(), m.exact) << m.name;
    EXPECT_EQ(find_method(m.name), &m);
  }
  EXPECT_EQ(find_method("nitsche"), nullptr);
  StrategyOptions o;
  o.method = "nitsche";
  EXPECT_EQ(o.validate(), "method: expected " + method_list(" | ") + ", found 'nitsche'");
}

TEST(MethodRegistry, DocsSceneMdHoldsTheRegistrysMethodTable) {
  std::ifstream in(std::string(C2D_SOURCE_DIR) + "/docs/scene.md");
  std::stringstream doc;
  doc << in.rdbuf();
  EXPECT_NE(doc.str().find(method_table_markdown()), std::string::npos)
      << "docs/scene.md must contain the method table, exactly:\n" << method_table_markdown();
}

TEST(Penalty, PenaltyMethodsSolveOnTheCondensedSurfaceWithOneFactorisation) {
  // The chain against the stop: K is factorised once (condensed onto the rows' unknowns) for a
  // method's whole solve, whatever its set iterations, stiffness raises or multiplier updates;
  // each then costs dense work on the rows only. The penalty solution must still be the
  // assembled one, (K + k GᵀG + k_eq AᵀA) u = f − k Gᵀ g0 + k_eq Aᵀ b, solved densely here,
  // u and its forces w = −k g, μ = −k_eq (A u − b) to 1e-9 relative (the dense reference
  // itself loses digits as k grows).
  ConstrainedProblem p = chain_against_stop();
  const Eigen::MatrixXd g(p.gap_jacobian);
  for (const std::string method : {"penalty", "adaptive_penalty", "auglag"}) {
    StrategyOptions o;
    o.method = method;
    o.penalty_factor = 1e3;
    const ConstraintSolution s = ConstraintStrategy::create(o)->solve(p);
    ASSERT_EQ(s.status, SolveStatus::kConverged) << method << ": " << s.message;
    EXPECT_EQ(s.factorizations, 1) << method;
    EXPECT_EQ(s.active[0], 1) << method;
    if (method == "adaptive_penalty") {
      EXPECT_GT(s.penalty_history.size(), 1u);
    }
    if (method == "auglag") {
      EXPECT_GT(s.history.size(), 2u);  // several multiplier rounds on the one factor
      continue;
    }
    const Eigen::MatrixXd a(p.eq_jacobian), k(p.stiffness);
    const double kg = s.penalty[0];
    const VecX ke = s.eq_penalty;
    const Eigen::MatrixXd lhs = k + kg * g.transpose() * g + a.transpose() * ke.asDiagonal() * a;
    const VecX rhs = p.load - kg * g.transpose() * p.gap0 +
                     a.transpose() * ke.asDiagonal() * p.eq_rhs;
    const VecX ref = lhs.fullPivLu().solve(rhs);
    EXPECT_LT((s.u - ref).cwiseAbs().maxCoeff(), 1e-9 * ref.cwiseAbs().maxCoeff()) << method;
    const double w = -kg * (p.gap0[0] + (g * ref)(0, 0));
    EXPECT_NEAR(s.contact_force[0], w, 1e-9 * w) << method;
    const VecX mu = -(ke.asDiagonal() * (a * ref - p.eq_rhs));
    EXPECT_LT((s.eq_multiplier - mu).cwiseAbs().maxCoeff(), 1e-9 * mu.cwiseAbs().maxCoeff())
        << method;
  }
}

TEST(Penalty, ErrorDecreasesLikeOneOverK) {
  // u2 of the spring chain under penalty: error ~ C / k, so ten times k, a tenth of the error.
  std::vector<double> errors;
  for (double factor : {1e2, 1e3, 1e4, 1e5}) {
    StrategyOptions o;
    o.method = "penalty";
    o.penalty_factor = factor;
    const ConstraintSolution s = ConstraintStrategy::create(o)->solve(spring_chain());
    ASSERT_EQ(s.status, SolveStatus::kConverged);
    errors.push_back(std::abs(s.u[1] - 0.27));
  }
  for (size_t i = 1; i < errors.size(); ++i) EXPECT_NEAR(errors[i - 1] / errors[i], 10.0, 0.5);
}

TEST(Penalty, HugeStiffnessKeepsItsDigitsOnTheCondensedSurface) {
  // k = 1e20 on the two bars' supports: assembled, K + k AᵀA kept no significant digits (the
  // method reported ill_conditioned). Condensed, each support is a compliance 1e-20 beside the
  // condensed stiffness, and the support displacement −w/k is a small number computed to its
  // own relative precision, so u2 = F / (k1 + k2) and the reactions come out exact; the forces
  // k·h agree with the solve's own, so nothing is reported.
  StrategyOptions o;
  o.method = "penalty";
  o.penalty_k = 1e20;
  const ConstraintSolution s = ConstraintStrategy::create(o)->solve(two_bars());
  ASSERT_EQ(s.status, SolveStatus::kConverged) << s.message;
  EXPECT_NEAR(s.u[1], 200000.0 / 860000.0, 1e-12);
  EXPECT_NEAR(s.eq_multiplier[0] + s.eq_multiplier[1], -200000.0, 1e-6);
  EXPECT_EQ(s.factorizations, 1);
}

TEST(RedundantRows, LagrangeSaysSingularIpoptDropsTheCopy) {
  ConstrainedProblem p = two_bars();
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(3, 3);
  a(0, 0) = 1;
  a(1, 2) = 1;
  a(2, 0) = 1;  // u1 = 0 twice
  p.eq_jacobian = sparse(a);
  p.eq_rhs = VecX::Zero(3);
  StrategyOptions o;
  o.method = "lagrange";
  const ConstraintSolution lag = ConstraintStrategy::create(o)->solve(p);
  EXPECT_EQ(lag.status, SolveStatus::kSingular) << lag.message;
  EXPECT_NE(lag.message.find("dependent"), std::string::npos) << lag.message;
  o.method = "ipopt";
  const ConstraintSolution ip = ConstraintStrategy::create(o)->solve(p);
  EXPECT_EQ(ip.status, SolveStatus::kConverged) << ip.message;
  EXPECT_NE(ip.message.find("1 duplicate"), std::string::npos) << ip.message;
  EXPECT_NEAR(ip.u[1], 200000.0 / 860000.0, 1e-8);
  // Contradictory copies (u1 = 0 and u1 = 0.1) cannot be dropped: a clear failure.
  p.eq_rhs[2] = 0.1;
  const ConstraintSolution bad = ConstraintStrategy::create(o)->solve(p);
  EXPECT_EQ(bad.status, SolveStatus::kFailed);
  EXPECT_NE(bad.message.find("inconsistent"), std::string::npos) << bad.message;
}

TEST(ActiveSetTracker, CountsChangesAndDetectsARecurringSet) {
  ActiveSetTracker t;
  const std::vector<char> a = {1, 0, 1}, b = {0, 1, 1};
  auto c = t.record(a);
  EXPECT_EQ(c.entering, 2);
  c = t.record(b);
  EXPECT_EQ(c.entering, 1);
  EXPECT_EQ(c.leaving, 1);
  EXPECT_FALSE(c.repeated);
  c = t.record(a);  // back to the first set: a cycle, not convergence
  EXPECT_TRUE(c.repeated);
  EXPECT_FALSE(c.unchanged);
  c = t.record(a);
  EXPECT_TRUE(c.unchanged);
}

// Default penalties (ConstrainedProblem::gap_local_stiffness): one stiffness per area κ per
// contact surface, the largest of its rows' local stiffness over their slave node's whole
// area, times each row's share of the surface. Three rows on surface 0 (node areas 1, 2, 1;
// local stiffnesses K_jj 4, 6, 2: κ = max(4, 3, 2) = 4), the last cut to a sliver of weight
// 1e-6 by the master's end (its κ over that sliver would be 2e6); one row on surface 1 (κ = 5);
// one of the seed's gap elements (no surface) keeps its own local stiffness.
TEST(DefaultPenalties, OneStiffnessPerAreaOfEachSurface) {
  ConstrainedProblem p;
  p.stiffness = sparse(Eigen::Vector<double, 5>(4.0, 6.0, 2.0, 5.0, 7.0).asDiagonal().toDenseMatrix());
  p.load = VecX::Zero(5);
  p.gap_jacobian = sparse(Eigen::MatrixXd::Identity(5, 5));
  p.gap0 = VecX::Zero(5);
  p.eq_jacobian = SpMat(0, 5);
  p.eq_rhs = VecX(0);
  p.gap_node_area = (VecX(5) << 1.0, 2.0, 1.0, 1.0, 0.0).finished();
  p.gap_area = (VecX(5) << 1.0, 2.0, 1e-6, 1.0, 0.0).finished();
  p.gap_surface = {0, 0, 0, 1, -1};
  const VecX k = p.gap_local_stiffness(RowMemory());
  EXPECT_DOUBLE_EQ(k[0], 4.0);
  EXPECT_DOUBLE_EQ(k[1], 8.0);   // twice the area, twice the stiffness: one penetration
  EXPECT_DOUBLE_EQ(k[2], 4e-6);  // the sliver: its share, not a κ of its own
  EXPECT_DOUBLE_EQ(k[3], 5.0);
  EXPECT_DOUBLE_EQ(k[4], 7.0);
  // Given per-row values (a load step keeps its first), they are used as they are.
  RowMemory kept;
  kept.gap_row_stiffness = VecX::Constant(5, 3.0);
  EXPECT_DOUBLE_EQ(p.gap_local_stiffness(kept)[2], 3.0);
}
