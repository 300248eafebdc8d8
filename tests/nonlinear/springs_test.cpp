// Springs in scenes (issue 17, item 3), against closed forms: a stiff block on ground springs
// sinks rigidly by F / (N k_y); a node-to-node spring stretched along its axis pulls with k Δ;
// turned by a transverse motion in a load-stepped run, the co-rotational spring pulls along its
// current direction with k (ℓ − L), where a linear run sees no force at all.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "constraints/contact_scene.hpp"
#include "constraints/contact_set.hpp"
#include "core/errors.hpp"
#include "core/model.hpp"
#include "core/probes.hpp"
#include "core/scene.hpp"
#include "nonlinear/load_stepper.hpp"
#include "nonlinear/load_stepper.hpp"

using namespace c2d;

namespace {

core::Results solve(const std::string& text, int* bottom_nodes = nullptr) {
  const core::Scene scene = core::parse_scene(text, "springs.toml");
  const core::Model model = core::build_model(scene);
  if (bottom_nodes) {
    core::SelectionSpec bottom;
    bottom.kind = core::SelectionSpec::Kind::kEdge;
    bottom.body = "a";
    bottom.name = "bottom";
    *bottom_nodes = static_cast<int>(core::select_nodes(model, bottom).size());
  }
  core::Results r;
  if (scene.analysis.geometric_nonlinearity) {
    nonlinear::StepperOptions o;
    o.steps = scene.analysis.steps;
    r = nonlinear::solve_geometric_nonlinear(model, scene.analysis, o);
  } else {
    r = nonlinear::solve_linear_static(model, scene.analysis);
  }
  if (r.status == SolveStatus::kConverged) r.probes = core::evaluate_probes(scene, model, r);
  return r;
}

const char* kStiff = R"(
[[material]]
name = "rigid"
E = 1e9
nu = 0.3
[[body]]
name = "a"
material = "rigid"
shape = { type = "rectangle", min = [0.0, 0.0], max = [1.0, 1.0] }
mesh = { size = 0.35 }
)";

}  // namespace

TEST(Springs, StiffBlockOnGroundSpringsSinksByTheLoadOverTheirStiffness) {
  for (const std::string stepped : {"false", "true"}) {
    const std::string text = "[analysis]\nkind = \"plane_stress\"\ngeometric_nonlinearity = " +
                             stepped + "\nsteps = 2\n" + kStiff + R"(
[[spring]]
name = "bed"
on = { body = "a", edge = "bottom" }
k = [50.0, 20.0]
[[load]]
on = { body = "a", edge = "top" }
total_force = [0.0, -3.0]
[[probe]]
name = "uy"
quantity = "uy"
on = { body = "a" }
reduce = "mean"
[[probe]]
name = "ux"
quantity = "ux"
on = { body = "a" }
reduce = "maxabs"
)";
    int n = 0;
    const core::Results r = solve(text, &n);
    ASSERT_EQ(r.status, SolveStatus::kConverged) << r.message;
    // The block is 1e7 times stiffer than its bed: it moves rigidly to 1e-6.
    EXPECT_NEAR(r.probes.at("uy") / (-3.0 / (n * 20.0)), 1.0, 1e-6) << stepped;
    EXPECT_LT(r.probes.at("ux"), 1e-9) << stepped;
  }
}

TEST(Springs, NodeToNodeSpringPullsAlongItsAxisAndTurnsWithItsNodes) {
  // Block a's bottom is moved (prescribed), block b is held; a spring of k = 40 joins a's
  // corner (1, 0) to b's corner (2, 0), 1 apart. The reaction at b's corner is the spring's pull.
  const double k = 40.0;
  auto scene = [&](bool stepped, const std::string& motion) {
    return "[analysis]\nkind = \"plane_stress\"\ngeometric_nonlinearity = " +
           std::string(stepped ? "true" : "false") + "\nsteps = 4\n" + kStiff + R"(
[[body]]
name = "b"
material = "rigid"
shape = { type = "rectangle", min = [2.0, 0.0], max = [3.0, 1.0] }
mesh = { size = 0.35 }
[[support]]
on = { body = "a", edge = "bottom" }
)" + motion + R"(
[[support]]
on = { body = "b" }
fix = ["ux", "uy"]
[[spring]]
between = [ { nearest = [1.0, 0.0] }, { nearest = [2.0, 0.0] } ]
k = 40.0
[[probe]]
name = "rx"
quantity = "reaction_x"
on = { nearest = [2.0, 0.0] }
[[probe]]
name = "ry"
quantity = "reaction_y"
on = { nearest = [2.0, 0.0] }
)";
  };
  // Along the axis: a moved 0.3 toward b shortens the spring by 0.3, linear or not.
  for (bool stepped : {false, true}) {
    const core::Results r = solve(scene(stepped, "ux = 0.3\nuy = 0.0"));
    ASSERT_EQ(r.status, SolveStatus::kConverged) << r.message;
    EXPECT_NEAR(r.probes.at("rx"), -0.3 * k, 1e-9 * k) << stepped;
    EXPECT_NEAR(r.probes.at("ry"), 0.0, 1e-9 * k) << stepped;
  }
  // Across it: a moved up by v = 0.5. Linear: no stretch, no force. Co-rotational: the spring
  // of length ℓ = √(1 + v²) pulls b toward a with k (ℓ − 1) along (−1, v)/ℓ... the reaction
  // holding b is the spring's internal force at b, k (ℓ − 1) (1, −v)/ℓ.
  const double v = 0.5, l = std::sqrt(1.0 + v * v);
  const core::Results lin = solve(scene(false, "ux = 0.0\nuy = 0.5"));
  ASSERT_EQ(lin.status, SolveStatus::kConverged) << lin.message;
  EXPECT_NEAR(lin.probes.at("rx"), 0.0, 1e-9 * k);
  const core::Results fin = solve(scene(true, "ux = 0.0\nuy = 0.5"));
  ASSERT_EQ(fin.status, SolveStatus::kConverged) << fin.message;
  EXPECT_NEAR(fin.probes.at("rx"), k * (l - 1.0) / l, 1e-9 * k);
  EXPECT_NEAR(fin.probes.at("ry"), -k * (l - 1.0) * v / l, 1e-9 * k);
}

TEST(Springs, MistakesAreLocated) {
  auto error = [](const std::string& spring) {
    try {
      core::parse_scene(std::string("[analysis]\n") + kStiff + "[[spring]]\n" + spring, "s.toml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  std::string m = error("on = { body = \"a\", edge = \"bottom\" }\nk = [0.0, 0.0]\n");
  EXPECT_NE(m.find("s.toml:"), std::string::npos) << m;
  EXPECT_NE(m.find("spring[0].k"), std::string::npos) << m;
  m = error("between = [ { nearest = [0.0, 0.0] } ]\nk = 1.0\n");
  EXPECT_NE(m.find("spring[0].between"), std::string::npos) << m;
  m = error("k = 1.0\n");
  EXPECT_NE(m.find("either 'on'"), std::string::npos) << m;
  m = error("on = { body = \"x\" }\nk = [1.0, 1.0]\n");
  EXPECT_NE(m.find("did you mean 'a'"), std::string::npos) << m;
}
