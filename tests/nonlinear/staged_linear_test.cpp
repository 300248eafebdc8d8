// One driver (issue 33, item 1): a linear analysis is the load stepper's small-strain system, so
// a linear run stages its loads by their amplitudes. A staged linear run must equal, at every
// stage, the one-step linear run of the loads that stage has reached: to round-off without
// contact and against a rigid flat (K is factorised once; the flat's rows are the same wherever
// a slave node is). Against an elastic base the small-strain rows are re-detected at each
// stage's deformed configuration (a linear run follows sliding), so a stage linearises about
// a slightly different master point than the one-step run: the two differ by a geometric term,
// O(slip × the master's rotation), bounded here. Reference: the one-step linear analysis of the
// same model (same mesh).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "constraints/contact_scene.hpp"
#include "constraints/contact_set.hpp"
#include "core/model.hpp"
#include "core/scene.hpp"
#include "nonlinear/load_stepper.hpp"

using namespace c2d;

namespace {

enum class Support { kRollers, kRigidFlat, kElasticBase };

/// A 2 × 0.5 block on a 4 × 1 base (base fixed below, the block's left edge on rollers), two
/// pressures on the block's top: `first` then `second`, each with its own amplitude text
/// (empty: none). The block sits on rollers, on a rigid flat at y = 1, or on the base (contact,
/// lagrange).
std::string scene_text(const std::string& first, double p1, const std::string& second, double p2,
                       Support support) {
  std::string s = R"(
[analysis]
kind = "plane_strain"
element = "T6"
steps = 2
[[material]]
name = "m"
E = 1000.0
nu = 0.3
[[body]]
name = "base"
material = "m"
shape = { type = "rectangle", min = [0.0, 0.0], max = [4.0, 1.0] }
mesh = { size = 0.25 }
[[body]]
name = "block"
material = "m"
shape = { type = "rectangle", min = [1.0, 1.0], max = [3.0, 1.5] }
mesh = { size = 0.2 }
[[support]]
on = { body = "base", edge = "bottom" }
fix = ["ux", "uy"]
[[support]]
on = { body = "block", edge = "left" }
fix = ["ux"]
)";
  if (support == Support::kRollers)
    s += R"(
[[support]]
on = { body = "block", edge = "bottom" }
fix = ["uy"]
)";
  else if (support == Support::kRigidFlat)
    s += R"(
[[obstacle]]
name = "flat"
type = "line"
point = [0.0, 1.0]
normal = [0.0, 1.0]
[[contact]]
slave = { body = "block", edge = "bottom" }
master = { obstacle = "flat" }
method = "lagrange"
)";
  else
    s += R"(
[[contact]]
slave = { body = "block", edge = "bottom" }
master = { body = "base", edge = "top" }
method = "lagrange"
)";
  auto load = [&](const std::string& amplitude, double p) {
    if (p == 0.0) return std::string();
    return "[[load]]\non = { body = \"block\", edge = \"top\" }\npressure = " + std::to_string(p) +
           "\n" + (amplitude.empty() ? "" : "amplitude = " + amplitude + "\n");
  };
  return s + load(first, p1) + load(second, p2);
}

struct Solved {
  std::vector<core::Results> stages;  ///< every converged step's fields
  core::Results last;
};

Solved solve(const std::string& text, bool staged) {
  const core::Scene scene = core::parse_scene(text, "staged.toml");
  const core::Model model = core::build_model(scene);
  const constraints::ContactSceneSpec spec = constraints::parse_contact_scene(scene, "");
  const constraints::ContactSet set(model, spec, scene);
  nonlinear::StepperOptions o;
  o.steps = staged ? scene.analysis.steps : 1;
  Solved out;
  o.on_state = [&](const nonlinear::StepRecord&, const core::Results& r) { out.stages.push_back(r); };
  out.last = nonlinear::solve_load_steps(model, scene.analysis, o, nullptr, spec.empty() ? nullptr : &set);
  return out;
}

void expect_same_state(const core::Results& staged, const core::Results& one_step,
                       double tolerance) {
  ASSERT_EQ(staged.status, SolveStatus::kConverged) << staged.message;
  ASSERT_EQ(one_step.status, SolveStatus::kConverged) << one_step.message;
  ASSERT_EQ(staged.displacement.size(), one_step.displacement.size());
  const double scale = one_step.displacement.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.0);
  EXPECT_LT((staged.displacement - one_step.displacement).cwiseAbs().maxCoeff(), tolerance * scale);
  // Forces against the largest load applied: 35 on the block's 2-long top.
  const double force = std::max(one_step.reaction.cwiseAbs().maxCoeff(), 70.0);
  EXPECT_LT((staged.reaction - one_step.reaction).cwiseAbs().maxCoeff(), 10 * tolerance * force);
}

class StagedLinear : public ::testing::TestWithParam<Support> {};

}  // namespace

TEST_P(StagedLinear, EachStageEqualsTheOneStepRunOfItsLoads) {
  const Support contact = GetParam();
  // Round-off (the same linear system and set), or the elastic base's geometric term: the
  // block's Poisson spread slides its nodes ~1e-3 along a base face that tilts ~1e-2 under them.
  const double tolerance = contact == Support::kElasticBase ? 1e-3 : 1e-10;
  // Stage 1 (λ = 0.5): 10 on the top; stage 2 (λ = 1): 10 + 25.
  const Solved staged = solve(scene_text("[[0.0, 0.0], [0.5, 1.0], [1.0, 1.0]]", 10.0,
                                         "[[0.0, 0.0], [0.5, 0.0], [1.0, 1.0]]", 25.0, contact),
                              true);
  ASSERT_EQ(staged.stages.size(), 2u);
  const Solved first = solve(scene_text("", 10.0, "", 0.0, contact), false);
  const Solved both = solve(scene_text("", 10.0, "", 25.0, contact), false);
  expect_same_state(staged.stages[0], first.last, tolerance);
  expect_same_state(staged.stages[1], both.last, tolerance);
  expect_same_state(staged.last, both.last, tolerance);
  EXPECT_DOUBLE_EQ(staged.stages[0].globals.at("load_factor"), 0.5);
}

// Prescribed motion stages like a load: the block's top pushed down by uy = −0.02 a(λ) with
// a = 0, 1 at λ = 0.5, 0.4 at λ = 1 (a press, then a partial release under displacement
// control). Each stage equals the one-step run of the value it has reached (−0.02, −0.008):
// round-off on rollers and on the rigid flat, the geometric term on the elastic base.
TEST_P(StagedLinear, PrescribedMotionStagesLikeALoad) {
  const Support contact = GetParam();
  const double tolerance = contact == Support::kElasticBase ? 1e-3 : 1e-10;
  const auto pressed = [&](double uy, const std::string& amplitude) {
    return scene_text("", 0.0, "", 0.0, contact) +
           "[[support]]\non = { body = \"block\", edge = \"top\" }\nuy = " + std::to_string(uy) +
           "\n" + (amplitude.empty() ? "" : "amplitude = " + amplitude + "\n");
  };
  const Solved staged = solve(pressed(-0.02, "[[0.0, 0.0], [0.5, 1.0], [1.0, 0.4]]"), true);
  ASSERT_EQ(staged.stages.size(), 2u);
  const Solved pressed_fully = solve(pressed(-0.02, ""), false);
  const Solved released = solve(pressed(-0.008, ""), false);
  expect_same_state(staged.stages[0], pressed_fully.last, tolerance);
  expect_same_state(staged.last, released.last, tolerance);
}

TEST(StagedLinear, WithoutAmplitudesALinearRunIsOneStep) {
  // Proportional loading: `steps` asks for nothing a linear run would not give at once.
  const Solved run = solve(scene_text("", 10.0, "", 25.0, Support::kElasticBase), true);
  ASSERT_EQ(run.last.status, SolveStatus::kConverged) << run.last.message;
  EXPECT_EQ(run.stages.size(), 1u);
  EXPECT_DOUBLE_EQ(run.last.globals.at("steps"), 1.0);
}

std::string support_name(const ::testing::TestParamInfo<Support>& info) {
  switch (info.param) {
    case Support::kRollers: return "rollers";
    case Support::kRigidFlat: return "rigid_flat";
    case Support::kElasticBase: return "elastic_base";
  }
  return "";
}

INSTANTIATE_TEST_SUITE_P(Contact, StagedLinear,
                         ::testing::Values(Support::kRollers, Support::kRigidFlat,
                                           Support::kElasticBase),
                         support_name);
