// The seed's chapter-2 cantilever (L = 3 m, h = 0.4 m, t = 0.2 m, E = 2.1e6, nu = 0.2,
// P = 3 t): tip deflection against Timoshenko beam theory, and a refinement study with the
// convergence orders of T3 and T6.
#include <gtest/gtest.h>

#include <cmath>

#include "core/model.hpp"
#include "core/probes.hpp"
#include "core/scene.hpp"
#include "nonlinear/load_stepper.hpp"

using namespace c2d;
using namespace c2d::core;

namespace {

const std::string kScene = std::string(C2D_SOURCE_DIR) + "/examples/cantilever.toml";
constexpr double kTimoshenko = -0.012208;  // P L^3/(3EI) + P L/(kappa G A), kappa = 5/6

struct Point {
  int dofs;
  double tip, energy;
};

Point solve(const std::vector<std::string>& overrides) {
  const Scene scene = load_scene(kScene, overrides);
  const Model model = build_model(scene);
  Results r = c2d::nonlinear::solve_linear_static(model, scene.analysis);
  EXPECT_EQ(r.status, SolveStatus::kConverged);
  const auto probes = evaluate_probes(scene, model, r);
  // Strain energy 1/2 fᵀu: converges monotonically from below at the rate of the energy norm.
  return {model.mesh.num_dofs(), probes.at("tip_uy"), 0.5 * model.external_force.dot(r.displacement)};
}

}  // namespace

TEST(Cantilever, T6TipDeflectionWithinHalfPercentUnder5000Dofs) {
  const Point p = solve({});
  EXPECT_LT(p.dofs, 5000);
  EXPECT_NEAR(p.tip, kTimoshenko, 0.005 * std::abs(kTimoshenko)) << "DOFs " << p.dofs;
}

TEST(Cantilever, RefinementStudyShowsConvergenceOrders) {
  // Uniform meshes h = 0.2, 0.1, 0.05 (no grading; h = 0.4 is pre-asymptotic for T3). The error of the strain energy against a
  // Richardson-extrapolated fine T6 value converges like h^(2p) in a smooth problem; the clamped
  // corners are singular (the stress ~ r^(λ-1) with λ ≈ 0.71 for a clamped-free 90° corner in
  // plane stress), which caps both orders near 2λ ≈ 1.4 in h for the energy. We assert that
  // T3 converges at least like h^1 and T6 at least like h^1.2, and that T6 is far more accurate
  // than T3 at the same DOFs, as the seed's convergence tables show.
  auto run = [](const char* element, double h) {
    return solve({std::string("analysis.element=") + element,
                  "body.beam.mesh.size=" + std::to_string(h), "body.beam.mesh.refine=[]"});
  };
  const Point f1 = run("T6", 0.025), f2 = run("T6", 0.0125);
  // Richardson with the asymptotic energy order of the corner singularity measured by f1, f2.
  const double e_ref = f2.energy + (f2.energy - f1.energy) / (std::pow(2.0, 1.4) - 1.0);
  for (const char* element : {"T3", "T6"}) {
    std::vector<Point> pts;
    for (double h : {0.2, 0.1, 0.05}) pts.push_back(run(element, h));
    for (size_t i = 1; i < pts.size(); ++i) {
      const double e0 = std::abs(pts[i - 1].energy - e_ref), e1 = std::abs(pts[i].energy - e_ref);
      const double order = std::log(e0 / e1) / std::log(2.0);
      std::printf("%s  DOFs %6d -> %6d  energy error %.3e -> %.3e  order in h %.2f  tip %.6f\n",
                  element, pts[i - 1].dofs, pts[i].dofs, e0 / e_ref, e1 / e_ref, order, pts[i].tip);
      EXPECT_GT(order, std::string(element) == "T3" ? 1.0 : 1.2) << element;
    }
  }
  const Point t3 = run("T3", 0.025), t6 = run("T6", 0.1);
  EXPECT_LT(t6.dofs, t3.dofs);
  EXPECT_LT(std::abs(t6.energy - e_ref), 0.1 * std::abs(t3.energy - e_ref))
      << "T6 with fewer DOFs should be 10x more accurate than T3";
}
