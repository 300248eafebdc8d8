// Parallel assembly (OpenMP over coloured chunks of elements): on two threads the same matrix and
// lift as on one to the last bit (both sum colour after colour), and the same as a plain loop over
// the elements through triplets to round-off (1e-13 relative to the largest entry: only the
// order of the sums differs).
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "core/assembler.hpp"
#include "core/elasticity_kernels.hpp"
#include "core/structured_grid.hpp"

using namespace c2d;
using namespace c2d::core;

namespace {

void expect_same_assembly(int n, int order) {
  const StructuredGrid g = make_structured_grid(n, order);
  // A prescribed displacement on the clamped edge, so the lift K_fc u_c is not zero.
  VecX u_full = VecX::Zero(g.mesh.num_dofs());
  for (int d = 0; d < g.mesh.num_dofs(); ++d)
    if (g.dofs.is_constrained(d)) u_full[d] = 1e-3 * (1 + d % 5);
  auto ke_of = [&](int e, LocalMatrix& ke) { ke = element_stiffness(g.mesh.element_coords(e), g.material); };
  Assembler serial(g.mesh, g.dofs), parallel(g.mesh, g.dofs);
  parallel.set_threads(2);
  VecX lift_s, lift_p;
  serial.assemble(ke_of, &u_full, &lift_s);
  parallel.assemble(ke_of, &u_full, &lift_p);
  EXPECT_EQ(serial.matrix().nonZeros(), parallel.matrix().nonZeros());
  EXPECT_TRUE(std::equal(serial.matrix().valuePtr(), serial.matrix().valuePtr() + serial.matrix().nonZeros(),
                         parallel.matrix().valuePtr()));
  EXPECT_TRUE(lift_s == lift_p);
  EXPECT_GT(lift_s.cwiseAbs().maxCoeff(), 0.0);
  // The reference: every element's matrix through triplets, in element order.
  std::vector<Eigen::Triplet<double>> t;
  VecX lift_r = VecX::Zero(g.dofs.num_free());
  LocalMatrix ke;
  for (int e = 0; e < g.mesh.num_elements(); ++e) {
    ke_of(e, ke);
    const int nn = g.mesh.nodes_per_element();
    for (int b = 0; b < 2 * nn; ++b)
      for (int a = 0; a < 2 * nn; ++a) {
        const int da = 2 * g.mesh.elements[e][a / 2] + a % 2, db = 2 * g.mesh.elements[e][b / 2] + b % 2;
        const int i = g.dofs.equation(da), j = g.dofs.equation(db);
        if (i >= 0 && j >= 0) t.emplace_back(i, j, ke(a, b));
        if (i >= 0 && j < 0) lift_r[i] += ke(a, b) * u_full[db];
      }
  }
  SpMat reference(g.dofs.num_free(), g.dofs.num_free());
  reference.setFromTriplets(t.begin(), t.end());
  const SpMat diff = reference - parallel.matrix();
  const double scale = reference.coeffs().cwiseAbs().maxCoeff();
  EXPECT_LT(diff.coeffs().cwiseAbs().maxCoeff(), 1e-13 * scale);
  EXPECT_LT((lift_r - lift_p).cwiseAbs().maxCoeff(), 1e-13 * lift_r.cwiseAbs().maxCoeff());
  // The colouring behind it: every element once, no node in two chunks of a colour.
  int elements = 0;
  const int ne = g.mesh.num_elements(), chunk = parallel.chunk_size();
  for (const auto& colour : parallel.colours()) {
    std::set<int> nodes;
    for (int first : colour) {
      std::set<int> own;
      for (int e = first; e < std::min(ne, first + chunk); ++e, ++elements)
        for (int i = 0; i < g.mesh.nodes_per_element(); ++i) own.insert(g.mesh.elements[e][i]);
      for (int v : own) EXPECT_TRUE(nodes.insert(v).second) << "chunk at " << first;
    }
  }
  EXPECT_EQ(elements, ne);
}

}  // namespace

TEST(ParallelAssembly, T3MatchesSerialToTheLastBit) { expect_same_assembly(60, 1); }
TEST(ParallelAssembly, T6MatchesSerialToTheLastBit) { expect_same_assembly(30, 2); }
