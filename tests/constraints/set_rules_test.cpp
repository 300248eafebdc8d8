// The one set engine's rules (constraints/set_rules.hpp) and its cycle detector, row by row:
// each decision against the complementarity condition it implements, by hand.
#include <gtest/gtest.h>

#include "constraints/active_set_tracker.hpp"
#include "constraints/set_rules.hpp"

namespace c2d::constraints {
namespace {

RuleScales scales(double c = 1.0e3) {
  RuleScales s;
  s.force_tolerance = 1e-12;
  s.gap_tolerance = 1e-12;
  s.c = c;
  return s;
}

// Primal-dual: a held row in tension leaves, a penetrating open row enters, a row on
// prescribed DOFs only (nothing to hold it with) never does.
TEST(SetRules, PrimalDualReleasesTensionAndClosesPenetration) {
  const PrimalDualRule rule;
  RowSolution r;
  r.held = true, r.force = -2.0;
  NormalDecision d = rule.normal(r, scales());
  EXPECT_FALSE(d.held);
  EXPECT_DOUBLE_EQ(d.residual, 2.0);  // max(0, −λ)
  r = RowSolution{};
  r.gap = -1e-3;
  EXPECT_TRUE(rule.normal(r, scales()).held);
  r.closable = false;
  EXPECT_FALSE(rule.normal(r, scales()).held);
}

// Primal-dual friction: a stick row beyond its bound slips along its force; a slipping row whose
// slip turned sticks; an entering row sticks within its allowance μ|g| and slips beyond it.
TEST(SetRules, PrimalDualStickSlip) {
  const PrimalDualRule rule;
  double residual = 0.0;
  RowSolution r;
  r.held = true, r.force = 10.0, r.tangent_force = -3.5, r.tangential = kStick;
  const NormalDecision d = rule.normal(r, scales());
  EXPECT_EQ(rule.tangential(r, d, 3.0, scales(), residual), kSlipMinus);
  EXPECT_DOUBLE_EQ(residual, 0.5);  // |λ_t| − bound
  r.tangential = kSlipPlus, r.slip = -1e-4;
  EXPECT_EQ(rule.tangential(r, d, 3.0, scales(), residual), kStick);
  r.tangential = kFree, r.slip = 2e-4, r.entry_slip_allowance = 3e-4;
  EXPECT_EQ(rule.tangential(r, d, 3.0, scales(), residual), kStick);
  r.entry_slip_allowance = 1e-4;
  EXPECT_EQ(rule.tangential(r, d, 3.0, scales(), residual), kSlipPlus);
}

// Semi-smooth: held iff λ − c g > 0; stick iff |λ_t + c s| ≤ bound, else slip along it; a
// slipping row whose trial turns against its slip passes through stick.
TEST(SetRules, SemiSmoothComparesTrialForces) {
  const SemiSmoothRule rule;
  RowSolution r;
  r.force = 0.0, r.gap = -1e-3;  // λ − c g = 1
  NormalDecision d = rule.normal(r, scales(1e3));
  EXPECT_TRUE(d.held);
  EXPECT_DOUBLE_EQ(d.normal, 1.0);
  EXPECT_DOUBLE_EQ(d.residual, 1.0);  // |λ − max(0, λ − c g)|
  r.gap = 2e-3, r.force = 1.0;         // λ − c g = −1: opens
  EXPECT_FALSE(rule.normal(r, scales(1e3)).held);
  r = RowSolution{};
  r.held = true, r.force = 1.0, r.tangent_force = 0.1, r.slip = 4e-4, r.tangential = kStick;
  d = rule.normal(r, scales(1e3));     // trial λ_t + c s = 0.5
  EXPECT_DOUBLE_EQ(d.trial_t, 0.5);
  double residual = 0.0;
  EXPECT_EQ(rule.tangential(r, d, 0.3, scales(1e3), residual), kSlipPlus);
  EXPECT_DOUBLE_EQ(residual, 0.2);     // |λ_t − bound|
  EXPECT_EQ(rule.tangential(r, d, 0.6, scales(1e3), residual), kStick);
  // A row slipping backwards whose trial turns forwards passes through stick (above the bound
  // the trial alone would send it straight to slip the other way).
  r.tangential = kSlipMinus, r.tangent_force = -0.3;
  d = rule.normal(r, scales(1e3));  // trial −0.3 + 0.4 = 0.1 > 0
  EXPECT_EQ(rule.tangential(r, d, 0.05, scales(1e3), residual), kStick);
  r.tangential = kSlipPlus;  // along its slip: the bound decides
  EXPECT_EQ(rule.tangential(r, d, 0.05, scales(1e3), residual), kSlipPlus);
  ASSERT_NE(rule.on_cycle(), nullptr);
  EXPECT_STREQ(rule.on_cycle()->name(), "primal-dual");
}

// Return map: the trial forces λ̂ − k g and λ̂_t + k_t s; a slipping row whose trial force
// turned against its slip passes through stick.
TEST(SetRules, ReturnMapUsesTrialForces) {
  const ReturnMapRule rule;
  EXPECT_TRUE(rule.regularised());
  RowSolution r;
  r.penalty = 100.0, r.tangent_penalty = 50.0, r.gap = -0.01, r.slip = 0.02;
  r.tangential = kStick;
  NormalDecision d = rule.normal(r, scales());
  EXPECT_TRUE(d.held);
  EXPECT_DOUBLE_EQ(d.normal, 1.0);
  EXPECT_DOUBLE_EQ(d.trial_t, 1.0);
  double residual = 0.0;
  EXPECT_EQ(rule.tangential(r, d, 0.3, scales(), residual), kSlipPlus);
  r.tangential = kSlipMinus;
  EXPECT_EQ(rule.tangential(r, d, 0.3, scales(), residual), kStick);
  r.force_estimate = 2.0, r.gap = 0.01;  // λ̂ − k g = 1: still held
  EXPECT_TRUE(rule.normal(r, scales()).held);
  r.gap = 0.03;
  EXPECT_FALSE(rule.normal(r, scales()).held);
}

// The cycle detector compares states, not only open/closed: a stick row turning to slip is a
// change; a state seen before (not the last) is a cycle; follow() takes a set as the last
// without remembering it.
TEST(SetRules, TrackerComparesStates) {
  ActiveSetTracker t;
  t.record({1, 0});
  ActiveSetTracker::Change c = t.record({2, 0});
  EXPECT_FALSE(c.unchanged);
  EXPECT_EQ(c.entering + c.leaving, 0);
  EXPECT_TRUE(t.record({2, 0}).unchanged);
  c = t.record({1, 0});
  EXPECT_TRUE(c.repeated);
  t.restart({1, 1});
  t.follow({0, 1});
  c = t.record({1, 0});
  EXPECT_FALSE(c.repeated);
  EXPECT_EQ(c.entering, 1);
  EXPECT_EQ(c.leaving, 1);
  EXPECT_FALSE(t.record({0, 1}).repeated);  // followed, not seen
  EXPECT_TRUE(t.record({1, 1}).repeated);   // the restart's set
}

}  // namespace
}  // namespace c2d::constraints
