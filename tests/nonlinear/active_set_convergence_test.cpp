// Issue 15, item 6: every contact method converges on a well-posed problem whose full-step
// active-set iteration wanders. A slender cantilever (L/h = 50, linear analysis) is pushed by a
// tip load onto a rigid floor 1 % of L below it; of the 201 slave nodes on its bottom edge only
// the tip corner ends in contact, but the unconstrained first solve penetrates about half of
// them. The floor reaction is checked against Euler-Bernoulli.
#include <gtest/gtest.h>

#include <string>

#include "constraints/contact_scene.hpp"
#include "constraints/contact_set.hpp"
#include "constraints/method_registry.hpp"
#include "core/model.hpp"
#include "core/scene.hpp"
#include "nonlinear/load_stepper.hpp"

using namespace c2d;
using namespace c2d::constraints;

namespace {

constexpr double kLength = 1000.0, kDepth = 20.0, kE = 210000.0, kLoad = 12.6, kFloorGap = 10.0;
constexpr double kMeshSize = 10.0;

// Euler-Bernoulli: the free tip deflection P L^3 / (3 E I) = 30 mm (3 % of L) exceeds the floor
// gap δ0, so the floor takes R = P − 3 E I δ0 / L^3 = 12.6 − 4.2 = 8.4 N. Shear adds
// 3EI/(κGAL²) ≈ 3e-4 to the compliance, and two T6 layers through the depth reproduce the
// beam's tip stiffness to about 1e-4, so R is held to 0.2 %.
constexpr double kInertia = kDepth * kDepth * kDepth / 12.0;  // thickness 1
constexpr double kReaction =
    kLoad - 3.0 * kE * kInertia * kFloorGap / (kLength * kLength * kLength);
constexpr double kReactionTolerance = 2e-3;

std::string cantilever_on_floor(const std::string& method) {
  return R"(
title = "Cantilever tip on a rigid floor"
units = "N, mm, MPa"
[analysis]
kind = "plane_stress"
element = "T6"
[[material]]
name = "steel"
E = 210000.0
nu = 0.3
thickness = 1.0
[[body]]
name = "beam"
material = "steel"
shape = { type = "rectangle", min = [0.0, 0.0], max = [1000.0, 20.0] }
mesh = { size = 10.0 }
[[support]]
on = { body = "beam", edge = "left" }
fix = ["ux", "uy"]
[[load]]
on = { body = "beam", edge = "right" }
total_force = [0.0, -12.6]
[[obstacle]]
name = "floor"
type = "line"
point = [0.0, -10.0]
normal = [0.0, 1.0]
[[contact]]
slave = { body = "beam", edge = "bottom" }
master = { obstacle = "floor" }
method = ")" +
         method + R"("
)";
}

class CantileverOnFloor : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(CantileverOnFloor, ConvergesWithTheTipReactionOfBeamTheory) {
  ASSERT_NEAR(kReaction, 8.4, 1e-12);
  const core::Scene scene = core::parse_scene(cantilever_on_floor(GetParam()), "floor.toml");
  const core::Model model = core::build_model(scene);
  const ContactSet contact(model, parse_contact_scene(scene, GetParam()), scene);
  ContactReport report;
  const core::Results results =
      nonlinear::solve_linear_static(model, scene.analysis, &contact, &report);

  ASSERT_EQ(results.status, SolveStatus::kConverged) << report.message;
  EXPECT_GE(report.rows, 200);
  // Only the tip corner carries force, and no row pulls.
  EXPECT_EQ(report.active_nodes, 1);
  for (const auto& node : report.nodes) {
    EXPECT_GE(node.force, 0.0) << "node at x = " << node.x.x();
    if (node.force > 0) {
      EXPECT_NEAR(node.x.x(), kLength, 1e-9 * kLength);
    }
  }
  // The method's default tolerance: 1e-6 × the smallest contact edge (≤ the mesh size).
  EXPECT_LE(report.max_penetration, 1e-6 * kMeshSize);
  EXPECT_NEAR(report.total_force / kReaction, 1.0, kReactionTolerance)
      << "floor reaction " << report.total_force << ", beam theory " << kReaction;
}

INSTANTIATE_TEST_SUITE_P(EveryMethod, CantileverOnFloor, ::testing::ValuesIn(method_names()),
                         [](const auto& info) { return info.param; });
