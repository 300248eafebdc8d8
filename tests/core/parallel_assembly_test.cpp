// Parallel assembly (OpenMP over coloured chunks of elements) against the serial loop: the same matrix and
// lift to round-off (1e-13 relative to the largest entry: only the order of the sums differs).
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
  const SpMat diff = serial.matrix() - parallel.matrix();
  const double scale = serial.matrix().coeffs().cwiseAbs().maxCoeff();
  EXPECT_EQ(serial.matrix().nonZeros(), parallel.matrix().nonZeros());
  EXPECT_LT(diff.coeffs().cwiseAbs().maxCoeff(), 1e-13 * scale);
  EXPECT_LT((lift_s - lift_p).cwiseAbs().maxCoeff(), 1e-13 * lift_s.cwiseAbs().maxCoeff());
  EXPECT_GT(lift_s.cwiseAbs().maxCoeff(), 0.0);
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

TEST(ParallelAssembly, T3MatchesSerialToRoundOff) { expect_same_assembly(60, 1); }
TEST(ParallelAssembly, T6MatchesSerialToRoundOff) { expect_same_assembly(30, 2); }
