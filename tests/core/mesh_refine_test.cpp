// Meshing large bodies coarse and subdividing (issue 19): the subdivided mesh is conforming,
// keeps the coarse mesh's angles, puts its boundary nodes on the curves, and carries an exact
// solution exactly (a patch test on a subdivided quarter disc).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <sstream>

#include "nonlinear/load_stepper.hpp"
#include "core/mesh_budget.hpp"
#include "core/mesh_refine.hpp"
#include "core/model.hpp"
#include "core/scene.hpp"

using namespace c2d;

namespace {

/// Unit square as two triangles, its four sides as curves 0..3.
core::CurveMesh unit_square() {
  core::CurveMesh m;
  m.nodes = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.elements = {{0, 1, 2, -1, -1, -1}, {0, 2, 3, -1, -1, -1}};
  m.segments = {{0, 1, 0}, {1, 2, 1}, {2, 3, 2}, {3, 0, 3}};
  return m;
}

/// How many elements use each corner-to-corner edge.
std::map<std::pair<int, int>, int> edge_uses(const core::Mesh& m) {
  std::map<std::pair<int, int>, int> uses;
  for (const auto& e : m.elements)
    for (int k = 0; k < 3; ++k) uses[{std::min(e[k], e[(k + 1) % 3]), std::max(e[k], e[(k + 1) % 3])}]++;
  return uses;
}

/// A quarter disc of radius 1 (from 0 to 90 degrees) in plane stress under an external pressure,
/// held by rollers on its two straight edges.
std::string quarter_disc_scene(double size, const char* element) {
  std::ostringstream os;
  os << "[analysis]\nkind = \"plane_stress\"\nelement = \"" << element << "\"\n"
     << "[[material]]\nname = \"m\"\nE = 1000.0\nnu = 0.25\n"
     << "[[body]]\nname = \"disc\"\nmaterial = \"m\"\n"
     << "shape = { type = \"disk_segment\", center = [0.0, 0.0], radius = 1.0, from_deg = 0.0, "
        "to_deg = 90.0 }\n"
     << "mesh = { size = " << size << " }\n"
     << "[[support]]\non = { body = \"disc\", edge = \"start\" }\nfix = [\"uy\"]\n"
     << "[[support]]\non = { body = \"disc\", edge = \"end\" }\nfix = [\"ux\"]\n"
     << "[[load]]\non = { body = \"disc\", edge = \"arc\" }\npressure = 2.0\n";
  return os.str();
}

}  // namespace

TEST(MeshRefine, SubdividedSquareIsConformingWithItsAnglesAndCurves) {
  core::CurveMesh m = unit_square();
  for (int k = 0; k < 3; ++k) core::subdivide(m, nullptr);
  core::make_quadratic(m, nullptr);
  core::renumber_spatially(m);
  const core::Mesh mesh = core::to_mesh(std::move(m), {"bottom", "right", "top", "left"});
  // 2·4³ triangles; T6 nodes on a (2·8 + 1)² grid.
  EXPECT_EQ(mesh.num_elements(), 128);
  EXPECT_EQ(mesh.num_nodes(), 17 * 17);
  double area = 0.0;
  for (int e = 0; e < mesh.num_elements(); ++e) area += mesh.corner_area(e);
  EXPECT_NEAR(area, 1.0, 1e-14);
  // Conforming: every edge has two elements except the 4·8 on the boundary.
  int boundary = 0;
  for (const auto& [edge, count] : edge_uses(mesh)) {
    EXPECT_LE(count, 2);
    boundary += count == 1;
  }
  EXPECT_EQ(boundary, 32);
  EXPECT_EQ(static_cast<int>(mesh.boundary_edges.size()), 32);
  // The children are similar to the parents (45-45-90 triangles), and each side keeps its name.
  EXPECT_NEAR(mesh.angle_quality().first, 45.0, 1e-9);
  for (const char* side : {"bottom", "right", "top", "left"}) {
    ASSERT_TRUE(mesh.edge_groups.count(side)) << side;
    EXPECT_EQ(mesh.edge_groups.at(side).size(), 8u) << side;
  }
  // T6 mid-side nodes halfway between their corners.
  for (const auto& e : mesh.elements)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR((mesh.nodes[e[3 + k]] - 0.5 * (mesh.nodes[e[k]] + mesh.nodes[e[(k + 1) % 3]])).norm(), 0.0, 1e-15);
}

TEST(MeshRefine, LargeQuarterDiscIsSubdividedWithItsNodesOnTheCircle) {
  // Sizes asking for about 70k triangles: gmsh meshes at twice the size, one subdivision.
  const core::Scene scene = core::parse_scene(quarter_disc_scene(0.005, "T6"), "disc.toml");
  ASSERT_GE(core::subdivision_levels(core::estimate_elements(scene.bodies[0]), core::kCoarseElements), 1);
  const core::Model model = core::build_model(scene);
  const core::Mesh& mesh = model.mesh;
  EXPECT_GT(mesh.num_elements(), 50000);
  EXPECT_GT(mesh.angle_quality().first, 25.0);
  EXPECT_EQ(mesh.angle_quality().second, 0);
  // Every node of every arc edge, corners and mid-sides, on the unit circle; the arc's edges
  // add up to its length (a polygon of chords of length h falls short by about h²/24).
  double arc = 0.0;
  for (int i : mesh.edge_groups.at("disc/arc")) {
    const auto& be = mesh.boundary_edges[i];
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(mesh.nodes[be.nodes[k]].norm(), 1.0, 1e-14);
    arc += (mesh.nodes[be.nodes[1]] - mesh.nodes[be.nodes[0]]).norm();
  }
  EXPECT_NEAR(arc, std::numbers::pi / 2, 1e-5);
  int boundary = 0;
  for (const auto& [edge, count] : edge_uses(mesh)) {
    EXPECT_LE(count, 2);
    boundary += count == 1;
  }
  EXPECT_EQ(boundary, static_cast<int>(mesh.boundary_edges.size()));
}

TEST(MeshRefine, PatchTestOnASubdividedQuarterDisc) {
  // An external pressure p on a disc gives σ = −p I everywhere, u = −p (1 − ν) / E · x, which
  // linear triangles hold exactly on any conforming mesh of any polygon: the subdivided mesh's
  // displacements match it to round-off.
  const core::Scene scene = core::parse_scene(quarter_disc_scene(0.005, "T3"), "disc.toml");
  ASSERT_GE(core::subdivision_levels(core::estimate_elements(scene.bodies[0]), core::kCoarseElements), 1);
  const core::Model model = core::build_model(scene);
  const core::Results r = c2d::nonlinear::solve_linear_static(model, scene.analysis);
  ASSERT_EQ(r.status, SolveStatus::kConverged);
  const double scale = -2.0 * (1.0 - 0.25) / 1000.0;
  double worst = 0.0;
  for (int n = 0; n < model.mesh.num_nodes(); ++n)
    worst = std::max(worst, (r.displacement.segment<2>(2 * n) - scale * model.mesh.nodes[n]).norm());
  EXPECT_LT(worst, 1e-10 * std::abs(scale));
  EXPECT_NEAR(r.nodal_stress.row(0).minCoeff(), -2.0, 1e-9);
  EXPECT_NEAR(r.nodal_stress.row(0).maxCoeff(), -2.0, 1e-9);
}
