// Multipoint constraints in scenes (issue 17, item 1): [[constraint]] rows of type `equal`,
// `linear` and `tie`, enforced by the run's constraint method in linear and load-stepped runs.
// The references are patch tests: a block on rollers whose top is held to one vertical
// displacement carries a uniform uniaxial stress, so its top moves by −F H / (E w) exactly
// (plane stress, thickness 1) and every representable method must reproduce it; two blocks
// tied across non-matching meshes behave as one block.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "constraints/contact_scene.hpp"
#include "constraints/contact_set.hpp"
#include "core/model.hpp"
#include "core/probes.hpp"
#include "core/scene.hpp"
#include "nonlinear/load_stepper.hpp"
#include "nonlinear/load_stepper.hpp"
#include "scene_run.hpp"

using namespace c2d;

namespace {

constexpr double kE = 1000.0, kWidth = 2.0, kHeight = 1.0, kForce = 10.0;

std::string block(const std::string& extra, const std::string& element = "T3") {
  return R"(
[analysis]
kind = "plane_stress"
element = ")" + element + R"("
[[material]]
name = "m"
E = 1000.0
nu = 0.3
[[body]]
name = "b"
material = "m"
shape = { type = "rectangle", min = [0.0, 0.0], max = [2.0, 1.0] }
mesh = { size = 0.3 }
[[support]]
on = { body = "b", edge = "bottom" }
fix = ["uy"]
[[support]]
on = { nearest = [0.0, 0.0] }
fix = ["ux"]
[[probe]]
name = "top_uy"
quantity = "uy"
on = { body = "b", edge = "top" }
reduce = "mean"
[[probe]]
name = "top_uy_max"
quantity = "uy"
on = { body = "b", edge = "top" }
reduce = "maxabs"
)" + extra;
}

using Solved = test::SceneRun;

Solved run(const std::string& text, const std::string& method, bool stepped = false) {
  core::Scene scene = core::parse_scene(text, "mpc.toml");
  scene.analysis.geometric_nonlinearity = stepped;
  return test::run_scene(scene, method);
}

// A point force on the top-right corner; the top edge held to one uy.
const std::string kEqualTop = R"(
[[load]]
on = { nearest = [2.0, 1.0] }
force = [0.0, -10.0]
[[constraint]]
name = "plate"
type = "equal"
on = { body = "b", edge = "top" }
dof = "uy"
)";

}  // namespace

TEST(EqualityConstraints, EqualTopCarriesAUniformStressWithEveryMethod) {
  const double exact = -kForce * kHeight / (kE * kWidth);
  for (const std::string method : {"lagrange", "ssn", "ipopt", "auglag", "penalty",
                                   "adaptive_penalty"}) {
    const Solved r = run(block(kEqualTop), method);
    ASSERT_EQ(r.results.status, SolveStatus::kConverged) << method << ": " << r.results.message;
    const double uy = r.results.probes.at("top_uy");
    // Exact methods to round-off (ipopt to its tolerance); penalty-type ones to their O(1/k)
    // (k = 1e3 × the local stiffness: the corner's row carries the whole force, 2e-3).
    const bool exact_method = method == "lagrange" || method == "ssn";
    const double tol = exact_method ? 1e-10 : method == "ipopt" ? 1e-6 : 5e-3;
    EXPECT_NEAR(uy / exact, 1.0, tol) << method;
    EXPECT_NEAR(r.results.probes.at("top_uy_max") / exact, 1.0, tol) << method;
    // One row per top node after the first, each reported with its multiplier.
    ASSERT_FALSE(r.report.equalities.empty()) << method;
    EXPECT_LT(r.report.max_equality_violation, (exact_method ? 1e-10 : 5e-3) * std::abs(exact))
        << method;
  }
}

TEST(EqualityConstraints, LinearRowPrescribesAMeanDisplacement) {
  // u_y(top left) + u_y(top right) = −2 d, with the top held to one uy: the top moves by −d,
  // and the multiplier is the force that takes: E d w / H (plane stress, free lateral).
  const double d = 0.004;
  const std::string extra = R"(
[[constraint]]
type = "equal"
on = { body = "b", edge = "top" }
dof = "uy"
[[constraint]]
name = "mean"
type = "linear"
terms = [ { on = { nearest = [0.0, 1.0] }, dof = "uy", coefficient = 1.0 },
          { on = { nearest = [2.0, 1.0] }, dof = "uy", coefficient = 1.0 } ]
value = -0.008
)";
  const Solved r = run(block(extra), "lagrange");
  ASSERT_EQ(r.results.status, SolveStatus::kConverged) << r.results.message;
  EXPECT_NEAR(r.results.probes.at("top_uy"), -d, 1e-12);
  // The force the structure needs, E d w / H, enters through the linear row, whose
  // multiplier acts on each of its two nodes (coefficient 1): 2 |μ| = E d w / H.
  double mean_force = 0.0;
  for (const auto& e : r.report.equalities)
    if (e.owner == 1) mean_force = e.multiplier;
  EXPECT_NEAR(2.0 * std::abs(mean_force), kE * d * kWidth / kHeight, 1e-8 * kE * d);
}

TEST(EqualityConstraints, TiedNonMatchingBlocksActAsOneBlock) {
  // Two blocks on non-matching meshes tied across their interface, pressed by a uniform
  // traction: the uniaxial state is linear in x and y, which a tie through the master's
  // interpolation reproduces exactly, so the top moves by −p (H1 + H2) / E.
  for (const std::string element : {"T3", "T6"})
    for (bool stepped : {false, true}) {
      std::string text = R"(
[analysis]
kind = "plane_stress"
element = ")" + element + R"("
geometric_nonlinearity = )" + (stepped ? "true" : "false") + R"(
steps = 3
[[material]]
name = "m"
E = 1000.0
nu = 0.3
[[body]]
name = "low"
material = "m"
shape = { type = "rectangle", min = [0.0, 0.0], max = [2.0, 1.0] }
mesh = { size = 0.23 }
[[body]]
name = "up"
material = "m"
shape = { type = "rectangle", min = [0.0, 1.0], max = [2.0, 1.5] }
mesh = { size = 0.17 }
[[support]]
on = { body = "low", edge = "bottom" }
fix = ["uy"]
[[support]]
on = { nearest = [0.0, 0.0] }
fix = ["ux"]
[[load]]
on = { body = "up", edge = "top" }
traction = [0.0, -10.0]
[[constraint]]
name = "glue"
type = "tie"
slave = { body = "up", edge = "bottom" }
master = { body = "low", edge = "top" }
[[probe]]
name = "top_uy"
quantity = "uy"
on = { body = "up", edge = "top" }
reduce = "mean"
)";
      const Solved r = run(text, "lagrange", stepped);
      const std::string name = element + (stepped ? " load-stepped" : " linear");
      ASSERT_EQ(r.results.status, SolveStatus::kConverged) << name << ": " << r.results.message;
      const double uy = r.results.probes.at("top_uy");
      if (!stepped) {
        EXPECT_NEAR(uy / (-10.0 * 1.5 / kE), 1.0, 1e-10) << name;
      } else {
        // St. Venant–Kirchhoff uniaxial stress: the same homogeneous state as one block;
        // against the linear answer it differs by the strain's own order (1.5 %).
        EXPECT_NEAR(uy / (-10.0 * 1.5 / kE), 1.0, 0.03) << name;
      }
      EXPECT_LT(r.report.max_equality_violation, 1e-12) << name;
    }
}
