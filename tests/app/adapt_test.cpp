// The error-driven adaptive loop against analytic and converged references.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "app/run/adapt.hpp"
#include "core/model.hpp"
#include "core/scene.hpp"
#include "core/size_field.hpp"

using namespace c2d;

namespace {

std::string example(const char* name) { return std::string(C2D_SOURCE_DIR) + "/examples/" + name; }

}  // namespace

TEST(SizeField, OptimalSizesFollowTheLocalParameter) {
  // Two T6 triangles of a unit square (edges 1, 1, √2): ξ = 1 keeps h, ξ = 4 with p = 2 halves
  // it, ξ = 1e6 stops at the shrink bound, ξ = 0 at the growth bound.
  core::Mesh mesh;
  mesh.order = 2;
  mesh.nodes = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0}, {1, 0.5}, {0.5, 0.5}, {0.5, 1}, {0, 0.5}};
  mesh.elements = {{0, 1, 2, 4, 5, 6}, {0, 2, 3, 6, 7, 8}};
  mesh.element_body = {0, 0};
  mesh.element_material = {0, 0};
  const double h = (2.0 + std::sqrt(2.0)) / 3.0;
  EXPECT_NEAR(core::element_size(mesh, 0), h, 1e-15);
  const core::SizeLimits limits{0.2, 2.0};
  const auto check = [&](double xi0, double xi1, double expect_vertex1, double expect_vertex3) {
    const auto f = core::optimal_size_fields(mesh, {xi0, xi1}, 1, limits);
    ASSERT_EQ(f.size(), 1u);
    ASSERT_EQ(f[0].triangles.size(), 2u);
    EXPECT_NEAR(f[0].sizes[0][1], expect_vertex1, 1e-14);  // node 1: element 0 only
    EXPECT_NEAR(f[0].sizes[1][2], expect_vertex3, 1e-14);  // node 3: element 1 only
    // Shared nodes take the smaller of the two.
    EXPECT_NEAR(f[0].sizes[0][0], std::min(expect_vertex1, expect_vertex3), 1e-14);
  };
  check(1.0, 4.0, h, h / 2);
  check(1e6, 0.0, 0.2 * h, 2.0 * h);
}

TEST(Adapt, HertzFromACoarseMeshReachesTheAnalyticContact) {
  // hertz_rigid_coarse.toml: 50 mm uniform T6, η = 2 %. Johnson §4.2 (rigid flat, plane
  // strain): p0 = 383.29 MPa, b = 1.6609 mm. Tolerances: 1 % on p0, 3 % on b.
  const core::Scene scene = core::load_scene(example("hertz_rigid_coarse.toml"), {});
  ASSERT_TRUE(scene.adapt.enabled);
  const app::AdaptRun run = app::solve_adaptive(scene, "", {}, {});
  ASSERT_TRUE(run.reached) << run.stop;
  ASSERT_GE(run.cycles.size(), 3u);
  for (size_t c = 1; c < run.cycles.size(); ++c)
    EXPECT_LT(run.cycles[c].global_parameter, run.cycles[c - 1].global_parameter) << "cycle " << c;
  EXPECT_LE(run.cycles.back().global_parameter, 1.0);
  const auto& probes = run.last->results.probes;
  EXPECT_NEAR(probes.at("p_max") / 383.29, 1.0, 0.01);
  EXPECT_NEAR(probes.at("half_width") / 1.6609, 1.0, 0.03);
  // The loop found the contact by itself: the smallest elements sit at the contact point, about
  // a tenth of the half-width, and the largest far from it.
  const core::Mesh& mesh = run.last->model.mesh;
  double h_near = 1e300, h_far_min = 1e300, h_max = 0.0;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const Vec2 c = (mesh.nodes[mesh.elements[e][0]] + mesh.nodes[mesh.elements[e][1]] +
                    mesh.nodes[mesh.elements[e][2]]) / 3;
    const double h = core::element_size(mesh, e);
    if (c.norm() < 5.0) h_near = std::min(h_near, h);
    else h_far_min = std::min(h_far_min, h);
    h_max = std::max(h_max, h);
  }
  EXPECT_LT(h_near, h_far_min);
  EXPECT_LT(h_near, 0.2 * 1.6609);
  EXPECT_GT(h_max, 100 * h_near);
  // Fewer DOFs than the hand-graded mesh of hertz_rigid.toml needs for the same accuracy: as
  // shipped (26,418 DOFs), and scaled coarser by 4 (3,794 DOFs), the coarsest mesh_scale of
  // {1, 1.5, 2, 3, 4, 6, 8} from which every finer one meets 1 % / 3 % (6 misses b by 3.3 %).
  const int adaptive = run.cycles.back().dofs;
  const core::Scene graded = core::load_scene(example("hertz_rigid.toml"), {});
  EXPECT_LT(adaptive, core::build_model(graded).mesh.num_dofs());
  const core::Scene graded4 = core::load_scene(example("hertz_rigid.toml"), {"analysis.mesh_scale=4"});
  EXPECT_LT(adaptive, core::build_model(graded4).mesh.num_dofs());
}

namespace {

// The seed's cantilever (examples/cantilever.toml) on a uniform T3 mesh of size h.
std::string cantilever_t3(double h, bool adapt) {
  return R"(
[analysis]
kind = "plane_stress"
element = "T3"
[[material]]
name = "concrete"
E = 2.1e6
nu = 0.2
thickness = 0.2
[[body]]
name = "beam"
material = "concrete"
shape = { type = "rectangle", min = [0.0, 0.0], max = [3.0, 0.4] }
mesh = { size = )" + std::to_string(h) + R"( }
[[support]]
on = { body = "beam", edge = "left" }
fix = ["ux", "uy"]
[[load]]
on = { body = "beam", edge = "right" }
total_force = [0.0, -3.0]
[[probe]]
name = "tip_uy"
quantity = "uy"
at = [3.0, 0.2]
)" + (adapt ? "[adapt]\ntarget = 0.04\nmax_cycles = 6\n" : "");
}

// The converged plane-stress tip deflection: uniform T6 meshes h = 0.0125 and 0.00625 give
// -0.01219268 and -0.01219276, extrapolated -0.0121928 (±5e-8). Timoshenko's 0.012208 is
// 0.13 % above it: beam theory does not restrain the clamped section's warping.
constexpr double kTip = -0.0121928;

double tip_of(const std::string& text, int* dofs) {
  const core::Scene scene = core::parse_scene(text, "cantilever.toml");
  const auto run = app::solve_scene(scene, "", {});
  *dofs = run->model.mesh.num_dofs();
  return run->results.probes.at("tip_uy");
}

}  // namespace

TEST(Adapt, CantileverRefinesTheClampedCornersAndBeatsUniformRefinement) {
  const core::Scene scene = core::parse_scene(cantilever_t3(0.1, true), "cantilever.toml");
  const app::AdaptRun run = app::solve_adaptive(scene, "", {}, {});
  ASSERT_TRUE(run.reached) << run.stop;
  const double tip = run.last->results.probes.at("tip_uy");
  EXPECT_NEAR(tip / kTip, 1.0, 0.002);
  // Smallest elements at the clamped corners (stress singularities), the largest near the
  // free end.
  const core::Mesh& mesh = run.last->model.mesh;
  double corner = 1e300, tip_zone = 0.0;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const Vec2 c = (mesh.nodes[mesh.elements[e][0]] + mesh.nodes[mesh.elements[e][1]] +
                    mesh.nodes[mesh.elements[e][2]]) / 3;
    const double h = core::element_size(mesh, e);
    if (std::min((c - Vec2(0, 0)).norm(), (c - Vec2(0, 0.4)).norm()) < 0.05)
      corner = std::min(corner, h);
    if (c.x() > 2.7) tip_zone = std::max(tip_zone, h);
  }
  double smallest = 1e300;
  for (int e = 0; e < mesh.num_elements(); ++e) smallest = std::min(smallest, core::element_size(mesh, e));
  EXPECT_NEAR(corner, smallest, 1e-12) << "the smallest element is not at a clamped corner";
  EXPECT_GT(tip_zone, 5 * corner);
  // Uniform refinement: h = 0.025 still misses 0.2 % (−0.6 %); h = 0.0125 meets it with more
  // DOFs than the adaptive mesh.
  int dofs_coarse = 0, dofs_fine = 0;
  EXPECT_GT(std::abs(tip_of(cantilever_t3(0.025, false), &dofs_coarse) / kTip - 1.0), 0.002);
  EXPECT_NEAR(tip_of(cantilever_t3(0.0125, false), &dofs_fine) / kTip, 1.0, 0.002);
  EXPECT_LT(run.cycles.back().dofs, dofs_fine);
}
