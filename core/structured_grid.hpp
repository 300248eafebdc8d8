// A structured mesh of the unit square (or a strip), for benchmarks and tests that need a mesh of
// a given size without gmsh: n × n squares, each cut into two T3 or two straight-sided T6.
#pragma once

#include "core/dof_map.hpp"
#include "core/material.hpp"
#include "core/mesh.hpp"

namespace c2d::core {

struct StructuredGrid {
  Mesh mesh;
  DofMap dofs;          ///< both displacements fixed on x = 0
  Material material;    ///< steel, plane strain
};

/// n ≥ 1 squares per side, order 1 (T3) or 2 (T6): 2 n² elements, 2 (order n + 1)² DOFs.
StructuredGrid make_structured_grid(int n, int order);
/// A strip of nx × ny unit-height-over-ny squares: nx / ny long, 1 high, clamped at x = 0.
StructuredGrid make_structured_grid(int nx, int ny, int order);

}  // namespace c2d::core
