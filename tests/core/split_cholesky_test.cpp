// core::SplitCholesky and mesh_fill_order's split (issue 19, item 2): the stiffness matrix
// factorised as two halves side by side plus the separator's dense Schur complement.
//  - Uniaxial tension of the unit square (rollers on x = 0, one point fixed in y, traction σ on
//    x = 1, plane strain): u_x = σ (1 − ν²) x / E, u_y = −σ ν (1 + ν) y / E, which T3 and T6
//    reproduce exactly; the split solve matches it to 1e-10 of the largest displacement.
//  - The split's halves share no element (no entry of K couples them); a spring that does is
//    moved into the separator, and the solve still equals CHOLMOD's factorisation of the whole
//    matrix (relative 1e-10, several right-hand sides at once).
//  - A matrix with a rigid-body mode (no supports) is reported singular, by SplitCholesky and
//    by SpdSolver (which then names it through LDLT's pivots).
//  - SpdSolver with a split fill order reports the split (ordering "corner_amd_split", the
//    separator's size), gives the same numbers to the last bit on one thread as on two, and
//    falls back to one factorisation when the split does not apply.
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <memory>
#include <numeric>
#include <vector>

#include "core/assembler.hpp"
#include "core/elasticity_kernels.hpp"
#include "core/fill_ordering.hpp"
#include "core/spd_solver.hpp"
#include "core/split_cholesky.hpp"
#include "core/structured_grid.hpp"

using namespace c2d;
using namespace c2d::core;

namespace {

constexpr double kSigma = 100.0;

/// The unit square with rollers on x = 0 (u_x = 0) and u_y = 0 at the origin; `free`: no
/// support at all.
StructuredGrid tension_square(int n, int order, bool free = false) {
  StructuredGrid g = make_structured_grid(n, order);
  g.dofs = DofMap(g.mesh.num_dofs());
  if (!free)
    for (int v = 0; v < g.mesh.num_nodes(); ++v)
      if (g.mesh.nodes[v].x() == 0.0) {
        g.dofs.constrain(2 * v, 0.0);
        if (g.mesh.nodes[v].y() == 0.0) g.dofs.constrain(2 * v + 1, 0.0);
      }
  g.dofs.finalize();
  return g;
}

SpMat stiffness(const StructuredGrid& g) {
  Assembler a(g.mesh, g.dofs);
  a.assemble([&](int e, LocalMatrix& ke) { ke = element_stiffness(g.mesh.element_coords(e), g.material); },
             nullptr, nullptr);
  SpMat k = a.matrix();
  k.makeCompressed();
  return k;
}

/// Consistent nodal forces of the traction σ on x = 1 (T6 edge: 1/6, 2/3, 1/6 of its force).
VecX tension_load(const StructuredGrid& g) {
  VecX f = VecX::Zero(g.dofs.num_free());
  const auto& m = g.mesh;
  auto add = [&](int node, double force) {
    if (const int q = g.dofs.equation(2 * node); q >= 0) f[q] += force;
  };
  for (const auto& e : m.elements)
    for (int k = 0; k < 3; ++k) {
      const int a = e[k], b = e[(k + 1) % 3];
      if (m.nodes[a].x() != 1.0 || m.nodes[b].x() != 1.0) continue;
      const double force = kSigma * std::abs(m.nodes[a].y() - m.nodes[b].y());
      if (m.order == 1) {
        add(a, force / 2);
        add(b, force / 2);
      } else {
        add(a, force / 6);
        add(b, force / 6);
        add(e[3 + k], 2 * force / 3);
      }
    }
  return f;
}

/// The largest error of u against the exact field, over the largest exact displacement.
double tension_error(const StructuredGrid& g, const VecX& u) {
  const double e = g.material.young, nu = g.material.poisson;
  double worst = 0, largest = 0;
  for (int v = 0; v < g.mesh.num_nodes(); ++v) {
    const Vec2& p = g.mesh.nodes[v];
    const double exact[2] = {kSigma * (1 - nu * nu) * p.x() / e, -kSigma * nu * (1 + nu) * p.y() / e};
    for (int d = 0; d < 2; ++d) {
      largest = std::max(largest, std::abs(exact[d]));
      const int q = g.dofs.equation(2 * v + d);
      worst = std::max(worst, std::abs((q >= 0 ? u[q] : 0.0) - exact[d]));
    }
  }
  return worst / largest;
}

class SplitCholeskyElements : public ::testing::TestWithParam<int> {};

}  // namespace

TEST_P(SplitCholeskyElements, SolvesUniaxialTensionExactly) {
  const StructuredGrid g = tension_square(40, GetParam());
  const FillOrder fill = mesh_fill_order(g.mesh, g.dofs, 0);
  ASSERT_EQ(fill.part.size(), fill.order.size());
  const SpMat k = stiffness(g);
  // No entry of K couples the two halves.
  for (int j = 0; j < k.outerSize(); ++j)
    for (SpMat::InnerIterator it(k, j); it; ++it)
      ASSERT_NE(fill.part[it.row()] + fill.part[j], 1) << "K(" << it.row() << ", " << j << ")";
  // OpenBLAS's thread count (when OpenBLAS is the BLAS) is the same after as before.
  const auto blas_threads = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  const int blas_before = blas_threads ? blas_threads() : 0;
  SplitCholesky split;
  ASSERT_TRUE(split.analyse(k, fill.order, fill.part, 2));
  const int sep = split.separator_size();
  EXPECT_GT(sep, 0);
  EXPECT_LT(sep, k.rows() / 20);
  ASSERT_EQ(split.factorize(k, 2), SolveStatus::kConverged);
  EXPECT_GT(split.pivot_ratio(), 1e-8);
  Eigen::MatrixXd x;
  ASSERT_EQ(split.solve(tension_load(g), x, 2), SolveStatus::kConverged);
  EXPECT_LT(tension_error(g, x.col(0)), 1e-10);
  if (blas_threads) {
    EXPECT_EQ(blas_threads(), blas_before);
  }
  // One thread: the halves one after the other, the same numbers.
  Eigen::MatrixXd x1;
  ASSERT_EQ(split.factorize(k, 1), SolveStatus::kConverged);
  ASSERT_EQ(split.solve(tension_load(g), x1, 1), SolveStatus::kConverged);
  EXPECT_LT((x1 - x).norm(), 1e-12 * x.norm());
}

TEST_P(SplitCholeskyElements, SpringAcrossTheSplitJoinsTheSeparator) {
  const StructuredGrid g = tension_square(30, GetParam());
  const FillOrder fill = mesh_fill_order(g.mesh, g.dofs, 0);
  SpMat k = stiffness(g);
  // A spring between the first unknown of each half (absent from the mesh's graph).
  int a = -1, b = -1;
  for (int q : fill.order) {
    if (a < 0 && fill.part[q] == 0) a = q;
    if (b < 0 && fill.part[q] == 1) b = q;
  }
  const double spring = 1e4;
  k.coeffRef(a, a) += spring;
  k.coeffRef(b, b) += spring;
  k.coeffRef(a, b) -= spring;
  k.coeffRef(b, a) -= spring;
  k.makeCompressed();
  SplitCholesky split;
  ASSERT_TRUE(split.analyse(k, fill.order, fill.part, 2));
  SplitCholesky plain;
  const SpMat k0 = stiffness(g);
  ASSERT_TRUE(plain.analyse(k0, fill.order, fill.part, 2));
  EXPECT_EQ(split.separator_size(), plain.separator_size() + 1);
  ASSERT_EQ(split.factorize(k, 2), SolveStatus::kConverged);
  const Eigen::MatrixXd rhs = Eigen::MatrixXd::Random(k.rows(), 3);
  Eigen::MatrixXd x;
  ASSERT_EQ(split.solve(rhs, x, 2), SolveStatus::kConverged);
  SpdSolver whole;
  ASSERT_EQ(whole.factorize(k), SolveStatus::kConverged);
  Eigen::MatrixXd y;
  ASSERT_EQ(whole.solve(rhs, y), SolveStatus::kConverged);
  EXPECT_LT((x - y).norm(), 1e-10 * y.norm());
}

TEST_P(SplitCholeskyElements, RigidBodyModeIsSingular) {
  const StructuredGrid g = tension_square(20, GetParam(), /*free=*/true);
  const FillOrder fill = mesh_fill_order(g.mesh, g.dofs, 0);
  const SpMat k = stiffness(g);
  SplitCholesky split;
  ASSERT_TRUE(split.analyse(k, fill.order, fill.part, 2));
  const SolveStatus st = split.factorize(k, 2);
  // A rigid-body mode leaves a pivot of round-off size, or none at all.
  EXPECT_TRUE(st == SolveStatus::kSingular || split.pivot_ratio() < 1e-14) << to_string(st);
  SpdSolver solver;
  solver.set_ordering(std::make_shared<const FillOrder>(fill), "corner_amd");
  EXPECT_EQ(solver.factorize(k), SolveStatus::kSingular);
}

TEST_P(SplitCholeskyElements, SpdSolverSplitsWhateverTheThreadsAndFallsBackWhenItCannot) {
  const StructuredGrid g = tension_square(40, GetParam());
  const SpMat k = stiffness(g);
  const VecX f = tension_load(g);
  const int threads = omp_get_max_threads();
  // SpdSolver on `count` threads with the mesh's split fill order: its report, u in `u`.
  auto solve_on = [&](int count, VecX& u) {
    omp_set_num_threads(count);
    SpdSolver solver;
    solver.set_ordering(std::make_shared<const FillOrder>(mesh_fill_order(g.mesh, g.dofs, 0)), "corner_amd");
    EXPECT_EQ(solver.factorize(k), SolveStatus::kConverged);
    EXPECT_EQ(solver.solve(f, u), SolveStatus::kConverged);
    return solver.report();
  };
  VecX u, u1;
  const SpdSolveReport two = solve_on(2, u);
  EXPECT_EQ(two.ordering, "corner_amd_split");
  EXPECT_GT(two.separator, 0);
  EXPECT_LT(tension_error(g, u), 1e-10);
  EXPECT_LT(two.relative_residual, 1e-12);
  EXPECT_EQ(solve_on(1, u1).ordering, "corner_amd_split");
  EXPECT_TRUE(u1 == u) << "largest difference " << (u1 - u).cwiseAbs().maxCoeff();
  // A split with one half empty does not apply: one factorisation in the given order.
  FillOrder lopsided = mesh_fill_order(g.mesh, g.dofs, 0);
  std::replace(lopsided.part.begin(), lopsided.part.end(), static_cast<signed char>(1),
               static_cast<signed char>(0));
  SpdSolver whole;
  whole.set_ordering(std::make_shared<const FillOrder>(lopsided), "corner_amd");
  ASSERT_EQ(whole.factorize(k), SolveStatus::kConverged);
  ASSERT_EQ(whole.solve(f, u), SolveStatus::kConverged);
  EXPECT_EQ(whole.report().ordering, "corner_amd");
  EXPECT_EQ(whole.report().separator, 0);
  EXPECT_LT(tension_error(g, u), 1e-10);
  omp_set_num_threads(threads);
}

TEST(SplitCholesky, TwoSeparateBodiesNeedNoSeparator) {
  // K = diag(K₁, K₁), the halves the two bodies: an empty separator, each body solved alone.
  const StructuredGrid g = tension_square(12, 2);
  const SpMat k1 = stiffness(g);
  const int n1 = static_cast<int>(k1.rows());
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < n1; ++j)
    for (SpMat::InnerIterator it(k1, j); it; ++it) {
      t.emplace_back(it.row(), j, it.value());
      t.emplace_back(n1 + it.row(), n1 + j, it.value());
    }
  SpMat k(2 * n1, 2 * n1);
  k.setFromTriplets(t.begin(), t.end());
  k.makeCompressed();
  std::vector<int> order(2 * n1);
  std::iota(order.begin(), order.end(), 0);
  std::vector<signed char> part(2 * n1, 0);
  std::fill(part.begin() + n1, part.end(), static_cast<signed char>(1));
  SplitCholesky split;
  ASSERT_TRUE(split.analyse(k, order, part, 2));
  EXPECT_EQ(split.separator_size(), 0);
  ASSERT_EQ(split.factorize(k, 2), SolveStatus::kConverged);
  EXPECT_GT(split.pivot_ratio(), 0.0);
  const VecX f1 = tension_load(g);
  VecX f(2 * n1);
  f << f1, 2.0 * f1;
  Eigen::MatrixXd x;
  ASSERT_EQ(split.solve(f, x, 2), SolveStatus::kConverged);
  EXPECT_LT(tension_error(g, x.col(0).head(n1)), 1e-10);
  EXPECT_LT(tension_error(g, 0.5 * x.col(0).tail(n1)), 1e-10);
}

TEST(SplitFillOrder, SmallMeshesCarryNoSplit) {
  const StructuredGrid g = make_structured_grid(10, 2);
  EXPECT_TRUE(mesh_fill_order(g.mesh, g.dofs).part.empty());
  EXPECT_FALSE(mesh_fill_order(g.mesh, g.dofs, 0).part.empty());
}

INSTANTIATE_TEST_SUITE_P(Elements, SplitCholeskyElements, ::testing::Values(1, 2),
                         [](const auto& info) { return info.param == 1 ? "T3" : "T6"; });
