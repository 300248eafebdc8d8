// What a contact result means, checked on whole solves: small-strain rows sum to the force
// transmitted; the recovered pressure is zero on open nodes and integrates to the row forces;
// mortar Hertz pressures converge with the mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "constraints/contact_scene.hpp"
#include "constraints/contact_set.hpp"
#include "core/model.hpp"
#include "core/scene.hpp"
#include "nonlinear/load_stepper.hpp"

using namespace c2d;
using namespace c2d::constraints;

namespace {

struct Solved {
  core::Results results;
  ContactReport report;
  double integral = 0.0;  ///< ∫ p ds over the slave surface (piecewise linear between nodes)
};

Solved solve(const std::string& toml, const std::string& method) {
  const core::Scene scene = core::parse_scene(toml, "semantics.toml");
  const core::Model model = core::build_model(scene);
  const ContactSceneSpec spec = parse_contact_scene(scene, method);
  const ContactSet contact(model, spec, scene);
  Solved s;
  s.results = nonlinear::solve_linear_static(model, scene.analysis, &contact, &s.report);
  // ∫ p ds: the pressure is linear between neighbouring slave nodes along the surface (the
  // scenes below have slave surfaces ordered by x), over the chords between them.
  std::map<double, std::pair<Vec2, double>> by_x;
  for (const auto& n : s.report.nodes) by_x[n.x.x()] = {n.x, n.pressure};
  for (auto it = by_x.begin(); std::next(it) != by_x.end(); ++it) {
    const auto& [a, pa] = it->second;
    const auto& [b, pb] = std::next(it)->second;
    s.integral += 0.5 * (pa + pb) * (b - a).norm();
  }
  return s;
}

/// Two blocks pressed together by 10 over a width of 2, soft enough (E = 100) that a linear run
/// strains the upper one by 10 %: rows rebuilt at the deformed configuration
/// would tilt and sum more than the load.
std::string soft_blocks(const std::string& detection, const std::string& element) {
  return R"(
[analysis]
element = ")" + element + R"("
[[material]]
name = "soft"
E = 100.0
nu = 0.3
[[material]]
name = "stiff"
E = 300.0
nu = 0.2
[[body]]
name = "low"
material = "stiff"
shape = { type = "rectangle", min = [0.0, 0.0], max = [2.0, 1.0] }
mesh = { size = 0.23 }
[[body]]
name = "up"
material = "soft"
shape = { type = "rectangle", min = [0.0, 1.0], max = [2.0, 2.0] }
mesh = { size = 0.17 }
[[support]]
on = { body = "low", edge = "bottom" }
fix = ["uy"]
[[support]]
on = { body = "low", edge = "left" }
fix = ["ux"]
[[support]]
on = { body = "up", edge = "left" }
fix = ["ux"]
[[load]]
on = { body = "up", edge = "top" }
traction = [0.0, -10.0]
[[contact]]
slave = { body = "up", edge = "bottom" }
master = { body = "low", edge = "top" }
detection = ")" + detection + R"("
)";
}

}  // namespace

TEST(SmallStrainContact, RowForcesSumToTheLoadAtLargeDisplacements) {
  // Reference normals: Σλ = 20 to round-off (before, deformed normals gave up to 8e-4 more).
  for (const char* detection : {"node_to_segment", "mortar"})
    for (const char* element : {"T3", "T6"}) {
      const Solved s = solve(soft_blocks(detection, element), "lagrange");
      ASSERT_EQ(s.results.status, SolveStatus::kConverged) << detection << " " << element;
      EXPECT_NEAR(s.report.total_force, 20.0, 20.0 * 1e-10) << detection << " " << element;
      EXPECT_NEAR(s.integral, 20.0, 20.0 * 1e-9) << detection << " " << element;
      EXPECT_LE(s.report.measured_penetration, s.report.penetration_tolerance);
    }
}

TEST(RecoveredPressure, ZeroOnOpenNodesAndCarriesTheRowForces) {
  // A cylinder (R = 50) pressed onto a rigid floor: a contact zone a few elements wide, with
  // open slave nodes beside it. Node-to-segment T3 and T6 (the corner-space recovery), mortar.
  const std::string scene = R"(
[analysis]
kind = "plane_strain"
element = "ELEMENT"
[[material]]
name = "steel"
E = 210000.0
nu = 0.3
[[body]]
name = "cylinder"
material = "steel"
shape = { type = "disk_segment", center = [0.0, 50.0], radius = 50.0, from_deg = 180.0, to_deg = 270.0 }
mesh = { size = 5.0, refine = [ { near_segment = [[-3.0, 0.0], [0.0, 0.0]], size = 0.1, radius = 0.0, growth = 1.3 } ] }
[[obstacle]]
name = "floor"
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[[support]]
on = { body = "cylinder", edge = "end" }
fix = ["ux"]
[[load]]
on = { body = "cylinder", edge = "start" }
total_force = [0.0, -2000.0]
[[contact]]
slave = { body = "cylinder", arc = { center = [0.0, 50.0], radius = 50.0, from_deg = -94.0, to_deg = -90.0 } }
master = { obstacle = "floor" }
detection = "DETECTION"
)";
  for (const char* detection : {"node_to_segment", "mortar"})
    for (const char* element : {"T3", "T6"}) {
      std::string toml = scene;
      toml.replace(toml.find("ELEMENT"), 7, element);
      toml.replace(toml.find("DETECTION"), 9, detection);
      const Solved s = solve(toml, "lagrange");
      ASSERT_EQ(s.results.status, SolveStatus::kConverged) << detection << " " << element;
      int open = 0;
      for (const auto& n : s.report.nodes)
        if (!n.active) {
          ++open;
          EXPECT_EQ(n.pressure, 0.0) << detection << " " << element << " node " << n.node;
        }
      EXPECT_GT(open, 3);
      EXPECT_GT(s.report.active_nodes, 5);
      // Σλ carries the load (1e-9); the recovered pressure integrates to Σλ (1e-6: the recovery
      // integrates along the curved edges, this check over the chords between nodes).
      EXPECT_NEAR(s.report.total_force, 2000.0, 2000.0 * 1e-9) << detection << " " << element;
      EXPECT_NEAR(s.integral, s.report.total_force, s.report.total_force * 1e-6)
          << detection << " " << element;
    }
}
