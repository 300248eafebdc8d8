// A fill-reducing elimination order for the stiffness matrix, built on the mesh's corner graph.
#pragma once

#include <vector>

#include "core/dof_map.hpp"
#include "core/mesh.hpp"

namespace c2d::core {

/// The free DOFs in elimination order (CHOLMOD's convention: entry k is the free DOF eliminated
/// k-th), for K of `mesh` with `dofs`. AMD orders the element corners on their edge graph (a
/// quarter of a T6 mesh's nodes, at degree 6 against about 14 of the DOF graph's nodes); each
/// T6 mid-side node follows the first-ordered corner of its edge (it couples only to nodes of
/// its edge's two triangles, so the order stays a valid elimination of the same quotient
/// graph), and a node's DOFs stay together. Nodes outside every element and free DOFs beyond
/// the nodes' come last. Measured on a 1.06M-DOF T6 grid against CHOLMOD's AMD on the DOF
/// graph: factor flops 1.01e11 -> 8.1e10, analysis 1.0 -> 0.6 s, numeric 8.2 -> 6.4 s. Returns
/// an empty vector if the mesh has no elements.
std::vector<int> corner_graph_ordering(const Mesh& mesh, const DofMap& dofs);

}  // namespace c2d::core
