// Robustness of the load-stepped path (issue 33, item 5), with every method of the registry:
// a block pressed and dragged off its master's free end is released and the run goes on (it
// ended `max_iterations` at λ = 0.504 with all six: Newton's residual sat at its round-off
// floor, 1.8e-12, above a test of 1.7e-12); the same with Coulomb friction; a stepper that
// cannot progress ends with a named status within its bound on attempts.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "constraints/method_registry.hpp"
#include "scene_run.hpp"

using namespace c2d;

namespace {

/// The slider starts at x = 4.5: it leaves the base's free end (x = 6) at λ = 0.5 and moves
/// on, free, to x = 7.5.
std::string drag_off_scene(const std::string& friction) {
  return test::block_drag_scene("T3", "node_to_segment", 4.5, friction);
}

class Robustness : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(Robustness, BlockDraggedOffItsMastersEndIsReleased) {
  for (const std::string friction : {"", "friction = { coefficient = 0.2 }"}) {
    SCOPED_TRACE(friction.empty() ? "frictionless" : "Coulomb 0.2");
    const core::Scene scene = core::parse_scene(drag_off_scene(friction), "drag_off.toml");
    const test::SceneRun r = test::run_scene(scene, GetParam());
    ASSERT_EQ(r.results.status, SolveStatus::kConverged) << r.results.message;
    // Free at the end: no contact, and the slider's top carries no force (a free block under a
    // prescribed motion; tolerance: the Newton test's 1e-8 relative to the contact force scale,
    // E h × 0.01 / 0.5 ≈ 4.6 per unit width, with room for round-off).
    EXPECT_EQ(r.report.active_nodes, 0);
    EXPECT_NEAR(r.results.probes.at("fx"), 0.0, 1e-6);
    EXPECT_NEAR(r.results.probes.at("fy"), 0.0, 1e-6);
    EXPECT_NEAR(r.results.globals.at("load_factor"), 1.0, 1e-12);
  }
}

TEST_P(Robustness, SteppingThatCannotProgressEndsStalled) {
  // The bound on attempts: 5 attempts cannot reach λ = 1 with 30 nominal steps.
  const core::Scene scene = core::parse_scene(drag_off_scene(""), "drag_off.toml");
  const core::Model model = core::build_model(scene);
  const constraints::ContactSet set(model, constraints::parse_contact_scene(scene, GetParam()),
                                    scene);
  nonlinear::StepperOptions o;
  o.steps = scene.analysis.steps;
  o.max_attempts = 5;
  std::vector<nonlinear::StepRecord> trace;
  const core::Results r =
      nonlinear::solve_geometric_nonlinear(model, scene.analysis, o, &trace, &set);
  EXPECT_EQ(r.status, SolveStatus::kStalled);
  EXPECT_NE(r.message.find("after 5 attempts"), std::string::npos) << r.message;
  EXPECT_EQ(trace.size(), 5u);
  EXPECT_NEAR(r.globals.at("load_factor"), 5.0 / 30.0, 1e-12);  // the converged state is kept
}

INSTANTIATE_TEST_SUITE_P(Methods, Robustness,
                         ::testing::ValuesIn(constraints::method_names()));
