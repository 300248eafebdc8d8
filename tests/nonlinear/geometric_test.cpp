// Geometric nonlinearity: the elastica against Mattiasson's tables, Newton's quadratic
// convergence, a stress-free rigid rotation through 90°, cutback, and an impossible load.
#include <gtest/gtest.h>

#include <cmath>

#include "core/model.hpp"
#include "core/scene.hpp"
#include "nonlinear/load_stepper.hpp"

using namespace c2d;
using namespace c2d::nonlinear;

namespace {

// The elastica scene with a chosen load parameter P L² / (E I) and number of steps.
core::Scene elastica(double load_parameter, int steps) {
  const double ei = 210000.0 * 10.0 * 1000.0 / 12.0;  // E t h³ / 12
  const double p = load_parameter * ei / 1.0e6;         // / L²
  return core::load_scene(std::string(C2D_SOURCE_DIR) + "/examples/elastica.toml",
                          {"load[0].total_force=[0.0, " + std::to_string(-p) + "]",
                           "analysis.steps=" + std::to_string(steps)});
}

core::Results run(const core::Scene& scene, std::vector<StepRecord>* trace = nullptr,
                  int newton_iterations = 25) {
  const core::Model model = core::build_model(scene);
  StepperOptions o;
  o.steps = scene.analysis.steps;
  o.newton.max_iterations = newton_iterations;
  core::Results r = solve_geometric_nonlinear(model, scene.analysis, o, trace);
  r.probes = {};
  // Tip displacement at the mid-depth node of the free end.
  int tip = -1;
  for (int n = 0; n < model.mesh.num_nodes(); ++n)
    if ((model.mesh.nodes[n] - Vec2(1000.0, 0.0)).norm() < 1e-9) tip = n;
  EXPECT_GE(tip, 0);
  r.globals["tip_ux"] = r.displacement[2 * tip];
  r.globals["tip_uy"] = r.displacement[2 * tip + 1];
  return r;
}

}  // namespace

TEST(Elastica, TipLoadParameterOneAndTwoWithinHalfAPercent) {
  // Mattiasson (1981): P L²/EI = 1: w/L = 0.30172, u/L = 0.05643; = 2: 0.49346, 0.16064.
  const double ref[2][3] = {{1.0, 0.30172, 0.05643}, {2.0, 0.49346, 0.16064}};
  for (const auto& c : ref) {
    core::Results r = run(elastica(c[0], 10));
    ASSERT_EQ(r.status, SolveStatus::kConverged) << r.message;
    EXPECT_NEAR(-r.globals["tip_uy"] / 1000.0 / c[1], 1.0, 0.005) << "load " << c[0];
    EXPECT_NEAR(-r.globals["tip_ux"] / 1000.0 / c[2], 1.0, 0.005) << "load " << c[0];
  }
}

TEST(Elastica, NewtonConvergesQuadratically) {
  std::vector<StepRecord> trace;
  run(elastica(2.0, 10), &trace);
  // In the asymptotic range (‖R‖∞ ≤ 0.1 N, with P = 350 N) and above round-off (≈ 2e-6 N here,
  // the internal forces being ~1e4 N), Newton squares the residual: r_{k+1} ≤ C r_k² with
  // C ≈ 2 N⁻¹ measured; a linearly converging iteration (r_{k+1} ≈ ρ r_k) fails C = 10.
  int checked = 0;
  for (const auto& s : trace) {
    const auto& r = s.newton.residual_norms;
    ASSERT_EQ(s.newton.status, SolveStatus::kConverged);
    EXPECT_LE(s.newton.iterations, 6) << "step " << s.step;
    for (size_t k = 0; k + 1 < r.size(); ++k) {
      const double a = r[k], b = r[k + 1];
      if (a > 0.1 || b < 1e-5) continue;
      EXPECT_LT(b, 10.0 * a * a) << "step " << s.step << " iteration " << k;
      ++checked;
    }
  }
  EXPECT_GT(checked, 5);
}

TEST(Elastica, OneStepIsCutBackAndStillConverges) {
  // P L²/EI = 10 (tip rotation ≈ 80°) in one step needs about 19 Newton iterations; with a
  // budget of 8 the step fails, is halved, and the run must still reach Mattiasson's
  // w/L = 0.81061, u/L = 0.55500.
  std::vector<StepRecord> trace;
  core::Results r = run(elastica(10.0, 1), &trace, 8);
  ASSERT_EQ(r.status, SolveStatus::kConverged) << r.message;
  int cut = 0;
  for (const auto& s : trace) cut += s.newton.status != SolveStatus::kConverged;
  EXPECT_GE(cut, 1);
  EXPECT_EQ(trace.front().newton.status, SolveStatus::kMaxIterations);
  EXPECT_NEAR(-r.globals["tip_uy"] / 1000.0 / 0.81061, 1.0, 0.005);
  EXPECT_NEAR(-r.globals["tip_ux"] / 1000.0 / 0.55500, 1.0, 0.005);
}

TEST(RigidRotation, NinetyDegreesInTenStepsStaysStressFree) {
  // A block whose left edge is rotated about the origin by prescribed displacements; the rest
  // follows freely. A rigid rotation must leave every stress below 1e-8 E.
  const core::Scene scene = core::parse_scene(R"(
[analysis]
kind = "plane_strain"
element = "T6"
geometric_nonlinearity = true
steps = 10
[[material]]
name = "m"
E = 1000.0
nu = 0.3
[[body]]
name = "block"
material = "m"
shape = { type = "rectangle", min = [0.0, 0.0], max = [2.0, 1.0] }
mesh = { size = 0.25 }
[[support]]
on = { body = "block", edge = "left" }
fix = ["ux", "uy"]
)", "rotation.toml");
  const core::Model model = core::build_model(scene);
  StepperOptions o;
  o.steps = 10;
  o.prescribe = [&](double lambda, VecX& u) {
    const double th = lambda * M_PI / 2;
    for (int n = 0; n < model.mesh.num_nodes(); ++n) {
      const Vec2 x = model.mesh.nodes[n];
      const Vec2 rx(std::cos(th) * x.x() - std::sin(th) * x.y(),
                    std::sin(th) * x.x() + std::cos(th) * x.y());
      u.segment<2>(2 * n) = rx - x;
    }
  };
  const core::Results r = solve_geometric_nonlinear(model, scene.analysis, o);
  ASSERT_EQ(r.status, SolveStatus::kConverged) << r.message;
  double smax = 0.0;
  for (const auto& s : r.element_stresses.at_points) smax = std::max(smax, s.cwiseAbs().maxCoeff());
  EXPECT_LT(smax, 1e-8 * 1000.0);
  // The far corner (2, 1) ends at (−1, 2).
  for (int n = 0; n < model.mesh.num_nodes(); ++n)
    if ((model.mesh.nodes[n] - Vec2(2, 1)).norm() < 1e-12) {
      EXPECT_NEAR(2 + r.displacement[2 * n], -1.0, 1e-9);
      EXPECT_NEAR(1 + r.displacement[2 * n + 1], 2.0, 1e-9);
    }
}

TEST(ImpossibleLoad, FailsWithTheLastConvergedStepKept) {
  // St. Venant–Kirchhoff has a limit in compression: the nominal stress E λ(λ² − 1)/2 of a
  // uniaxial stretch λ peaks at E / (3√3) = 0.192 E (λ = 1/√3). A pressure of 0.5 E on a free
  // block cannot be carried: the analysis must stop with a failed status and keep the last
  // converged load factor, below 0.192 / 0.5 plus the Poisson effect's margin.
  const core::Scene scene = core::parse_scene(R"(
[analysis]
kind = "plane_stress"
element = "T3"
geometric_nonlinearity = true
steps = 10
[[material]]
name = "m"
E = 1000.0
nu = 0.0
[[body]]
name = "block"
material = "m"
shape = { type = "rectangle", min = [0.0, 0.0], max = [1.0, 1.0] }
mesh = { size = 0.5 }
[[support]]
on = { body = "block", edge = "bottom" }
fix = ["uy"]
[[support]]
on = { body = "block", edge = "left" }
fix = ["ux"]
[[load]]
on = { body = "block", edge = "top" }
traction = [0.0, -500.0]
)", "crush.toml");
  const core::Model model = core::build_model(scene);
  StepperOptions o;
  o.steps = 10;
  std::vector<StepRecord> trace;
  const core::Results r = solve_geometric_nonlinear(model, scene.analysis, o, &trace);
  EXPECT_NE(r.status, SolveStatus::kConverged);
  EXPECT_NE(r.message.find("failed after"), std::string::npos) << r.message;
  const double lambda = r.globals.at("load_factor");
  // With ν = 0 the block is in uniaxial stress, so the cutbacks close in on the limit itself:
  // 8 halvings of the 0.1 increment resolve it to 0.1 / 256.
  const double limit = 1.0 / (3 * std::sqrt(3.0)) / 0.5;
  EXPECT_LE(lambda, limit * (1 + 1e-6));
  EXPECT_GT(lambda, limit - 0.1 / 256);
  EXPECT_TRUE(r.displacement.allFinite());
}

TEST(InvertedElement, IsNamedWithItsElementAndStep) {
  // A unit block whose top is pushed down by 1.5 in one step: every element's Jacobian turns
  // negative, so no step size can carry it. The run must end `inverted_element`, naming an
  // element (1-based) and the load step, not a solver's internal flag.
  const core::Scene scene = core::parse_scene(R"(
[analysis]
element = "T3"
geometric_nonlinearity = true
steps = 1
[[material]]
name = "m"
E = 100.0
nu = 0.3
[[body]]
name = "b"
material = "m"
shape = { type = "rectangle", min = [0.0, 0.0], max = [1.0, 1.0] }
mesh = { size = 0.5 }
[[support]]
on = { body = "b", edge = "bottom" }
fix = ["ux", "uy"]
[[support]]
on = { body = "b", edge = "top" }
uy = -1.5
)", "inverted.toml");
  const core::Model model = core::build_model(scene);
  StepperOptions o;
  o.steps = 1;
  const core::Results r = solve_geometric_nonlinear(model, scene.analysis, o, nullptr);
  EXPECT_EQ(r.status, SolveStatus::kInvertedElement) << r.message;
  EXPECT_NE(r.message.find("load step to"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("is inverted (J <= 0)"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("element "), std::string::npos) << r.message;
  EXPECT_EQ(r.message.find("KINSOL"), std::string::npos) << r.message;
}
