// A fill-reducing elimination order for the stiffness matrix, built on the mesh's corner graph.
#pragma once

#include <memory>
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

/// The mesh's corner graph behind a FillOrder (fill_ordering.cpp).
class CornerGraph;

/// A fill order for SpdSolver, with a two-way split for its two-thread factorisation
/// (core/split_cholesky.hpp), and for TailCholesky a fill order with chosen unknowns last.
struct FillOrder {
  std::vector<int> order;         ///< the free DOFs in elimination order
  /// Per free DOF: 0 or 1, the two halves, or 2, the separator between them (no element holds
  /// DOFs of both halves). Empty: no split.
  std::vector<signed char> part;
  /// The corner graph `order` came from (mesh_fill_order), or null.
  std::shared_ptr<const CornerGraph> graph;

  /// `order` with the free DOFs `tail` moved last, both parts in their relative order.
  std::vector<int> moved_last(const std::vector<int>& tail) const;
  /// The free DOFs in an elimination order with `tail` last: CAMD on the corner graph with the
  /// corners that hold tail DOFs constrained last, expanded as `order` is (empty without a
  /// graph). Moving the tail out of an order made without it can cost far more fill than
  /// ordering around it: on a slender beam pressed along its length on a floor
  /// (examples/slender_floor.toml, 6k DOFs) the tail is the beam's whole bottom edge, and
  /// `order` with it moved last sweeps the beam end to end, each column reaching every tail
  /// node behind it: 1.6M factor entries, where this order has 0.34M (the factor without a
  /// tail, 0.1M). On compact bodies either may be smaller (Hertz on a block: 0.26M moved last,
  /// 0.29M here), so TailCholesky analyses both and keeps the one of fewer flops.
  std::vector<int> tail_last(const std::vector<int>& tail) const;
};

/// Below this many free DOFs the fill order carries no split: one factorisation costs a few
/// tens of milliseconds and the second thread saves little of it.
constexpr int kMinSplitUnknowns = 40000;

/// corner_graph_ordering, plus (from `min_split_unknowns` free DOFs on) a split: METIS bisects
/// the corner graph by a vertex separator (CHOLMOD's cholmod_bisect); a T6 mid-side node joins
/// its edge's half, the separator when both its corners are in it; nodes outside every element
/// and free DOFs beyond the nodes' join the separator. No split when CHOLMOD was built without
/// METIS or a half is empty.
FillOrder mesh_fill_order(const Mesh& mesh, const DofMap& dofs,
                          int min_split_unknowns = kMinSplitUnknowns);

}  // namespace c2d::core
