// Zienkiewicz-Zhu estimate: zero for a field the mesh represents exactly (covered with the
// patch tests too), and a global parameter that decreases under refinement (cantilever).
#include <gtest/gtest.h>

#include "core/model.hpp"
#include "core/scene.hpp"
#include "nonlinear/load_stepper.hpp"

using namespace c2d;
using namespace c2d::core;

namespace {
std::string example(const char* name) { return std::string(C2D_SOURCE_DIR) + "/examples/" + name; }
}  // namespace

TEST(ZienkiewiczZhu, ZeroForUniformTension) {
  // A plate in uniform tension: the exact stress is constant, so σ* = σ_h and ||e|| = 0.
  const Scene scene = parse_scene(R"(
[analysis]
element = "T6"
[[material]]
name = "m"
E = 1000.0
nu = 0.25
[[body]]
name = "plate"
material = "m"
shape = { type = "rectangle", min = [0.0, 0.0], max = [2.0, 1.0] }
mesh = { size = 0.3 }
[[support]]
on = { edge = "left" }
fix = ["ux"]
[[support]]
on = { nearest = [0.0, 0.0] }
fix = ["uy"]
[[load]]
on = { edge = "right" }
traction = [5.0, 0.0]
)", "uniform.toml");
  const Model model = build_model(scene);
  const Results r = c2d::nonlinear::solve_linear_static(model, scene.analysis);
  ASSERT_EQ(r.status, SolveStatus::kConverged);
  EXPECT_LT(r.error.error_norm, 1e-9 * r.error.energy_norm);
  EXPECT_LT(r.error.global_parameter, 1e-8);
  for (int n = 0; n < model.mesh.num_nodes(); ++n) EXPECT_NEAR(r.nodal_stress(0, n), 5.0, 1e-9);
}

TEST(ZienkiewiczZhu, GlobalParameterDecreasesUnderRefinement) {
  for (const char* element : {"T3", "T6"}) {
    double previous = 1e300;
    for (double size : {0.2, 0.1, 0.05}) {
      const Scene scene = load_scene(example("cantilever.toml"),
                                     {std::string("analysis.element=") + element,
                                      "body.beam.mesh.size=" + std::to_string(size),
                                      "body.beam.mesh.refine=[]"});
      const Model model = build_model(scene);
      const Results r = c2d::nonlinear::solve_linear_static(model, scene.analysis);
      ASSERT_EQ(r.status, SolveStatus::kConverged);
      EXPECT_LT(r.error.global_parameter, previous) << element << " h = " << size;
      previous = r.error.global_parameter;
      // ξ_e: its RMS over the elements equals ξ_g by construction (equidistribution).
      double sum = 0;
      for (double x : r.error.local_parameter) sum += x * x;
      EXPECT_NEAR(std::sqrt(sum / r.error.local_parameter.size()), r.error.global_parameter,
                  1e-12 * r.error.global_parameter);
    }
  }
}
