// Patch tests: a linear displacement field imposed on the boundary of a distorted patch is
// reproduced exactly inside (to 1e-10 relative), and every stress point carries the constant
// stress D eps, for T3 and for T6 (straight-sided, mid-side nodes at the edge midpoints).
#include <gtest/gtest.h>

#include <map>

#include "core/model.hpp"
#include "core/stress_recovery.hpp"
#include "nonlinear/load_stepper.hpp"

using namespace c2d;
using namespace c2d::core;

namespace {

// A 2 x 2 square split into 8 triangles around two distorted interior nodes... built from a
// 4 x 4 node grid with every interior node moved off the grid.
Mesh distorted_t3_patch() {
  Mesh m;
  m.order = 1;
  const int n = 4;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      Vec2 p(2.0 * i / (n - 1), 2.0 * j / (n - 1));
      if (i > 0 && i < n - 1 && j > 0 && j < n - 1)
        p += Vec2(0.13 * ((i + 2 * j) % 3 - 1), -0.11 * ((2 * i + j) % 3 - 1));
      m.nodes.push_back(p);
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
      if ((i + j) % 2 == 0) {
        m.elements.push_back({a, b, c, -1, -1, -1});
        m.elements.push_back({a, c, d, -1, -1, -1});
      } else {
        m.elements.push_back({a, b, d, -1, -1, -1});
        m.elements.push_back({b, c, d, -1, -1, -1});
      }
    }
  m.element_body.assign(m.elements.size(), 0);
  m.element_material.assign(m.elements.size(), 0);
  m.orient_counter_clockwise();
  m.build_boundary();
  return m;
}

Mesh to_t6(const Mesh& t3) {
  Mesh m = t3;
  m.order = 2;
  std::map<std::pair<int, int>, int> mid;
  for (auto& el : m.elements)
    for (int k = 0; k < 3; ++k) {
      const int a = el[k], b = el[(k + 1) % 3];
      auto [it, inserted] = mid.try_emplace({std::min(a, b), std::max(a, b)}, m.num_nodes());
      if (inserted) m.nodes.push_back(0.5 * (m.nodes[a] + m.nodes[b]));
      el[3 + k] = it->second;
    }
  m.build_boundary();
  return m;
}

void run_patch(const Mesh& mesh, PlaneState state) {
  Model model;
  model.mesh = mesh;
  Material mat;
  mat.young = 1000.0;
  mat.poisson = 0.3;
  mat.thickness = 0.5;
  mat.state = state;
  model.materials = {mat};
  // u = a + G x with a full gradient G (stretch, shear and rotation).
  const Vec2 a(0.01, -0.02);
  Eigen::Matrix2d g;
  g << 1e-3, 2e-3, -0.5e-3, 3e-3;
  auto exact = [&](const Vec2& x) -> Vec2 { return a + g * x; };
  std::vector<bool> boundary(mesh.num_nodes(), false);
  for (const auto& be : mesh.boundary_edges)
    for (int v : be.nodes)
      if (v >= 0) boundary[v] = true;
  model.dofs = DofMap(mesh.num_dofs());
  for (int n = 0; n < mesh.num_nodes(); ++n)
    if (boundary[n]) {
      model.dofs.constrain(2 * n, exact(mesh.nodes[n]).x());
      model.dofs.constrain(2 * n + 1, exact(mesh.nodes[n]).y());
    }
  model.dofs.finalize();
  ASSERT_GT(model.dofs.num_free(), 0);
  model.external_force = VecX::Zero(mesh.num_dofs());
  AnalysisSpec analysis;
  const Results r = c2d::nonlinear::solve_linear_static(model, analysis);
  ASSERT_EQ(r.status, SolveStatus::kConverged);
  const double uscale = 0.03;
  for (int n = 0; n < mesh.num_nodes(); ++n)
    EXPECT_LT((r.displacement.segment<2>(2 * n) - exact(mesh.nodes[n])).norm(), 1e-10 * uscale)
        << "node " << n;
  const Voigt eps(g(0, 0), g(1, 1), g(0, 1) + g(1, 0));
  const Voigt sigma = mat.elasticity() * eps;
  for (int e = 0; e < mesh.num_elements(); ++e)
    for (int k = 0; k < r.element_stresses.at_points[e].cols(); ++k)
      EXPECT_LT((r.element_stresses.at_points[e].col(k) - sigma).norm(), 1e-10 * sigma.norm());
  // Every smoothing reproduces a constant field, and the ZZ estimate of it is zero.
  for (int n = 0; n < mesh.num_nodes(); ++n)
    EXPECT_LT((r.nodal_stress.col(n) - sigma).norm(), 1e-10 * sigma.norm());
  EXPECT_LT(r.error.error_norm, 1e-10 * r.error.energy_norm);
}

}  // namespace

TEST(PatchTest, T3DistortedPlaneStress) { run_patch(distorted_t3_patch(), PlaneState::kPlaneStress); }
TEST(PatchTest, T3DistortedPlaneStrain) { run_patch(distorted_t3_patch(), PlaneState::kPlaneStrain); }
TEST(PatchTest, T6DistortedPlaneStress) {
  run_patch(to_t6(distorted_t3_patch()), PlaneState::kPlaneStress);
}
TEST(PatchTest, T6DistortedPlaneStrain) {
  run_patch(to_t6(distorted_t3_patch()), PlaneState::kPlaneStrain);
}
