// Contact detection: where each slave node is relative to its master (an analytic obstacle,
// boundary edges of another body, or a paired node), as a signed gap, a normal and the master
// nodes with their weights. Negative gap = penetration. The normal points from the master
// toward the free side, so the linearised gap is  δg = n · (δu_slave − Σ_a w_a δu_a).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/mesh.hpp"
#include "core/types.hpp"

namespace c2d::constraints {

/// A rigid analytic obstacle with an exact gap and normal.
struct Obstacle {
  enum class Type { kLine, kCircle };
  std::string name;
  Type type = Type::kLine;
  Vec2 point = Vec2::Zero();       ///< line: a point on it
  Vec2 normal = Vec2::UnitY();     ///< line: unit normal toward the free side
  Vec2 center = Vec2::Zero();      ///< circle
  double radius = 0.0;             ///< circle
  bool inside = false;             ///< circle: bodies stay inside it (a rigid hole)

  /// Signed gap of point x and the normal toward the free side there.
  void gap(const Vec2& x, double& g, Vec2& n) const;
};

/// One boundary edge of a master surface: 2 nodes (linear) or 3 (quadratic: ends, then middle),
/// ordered with the body on the left so the outward normal is (t_y, −t_x).
struct MasterEdge {
  std::array<int, 3> nodes{-1, -1, -1};
  int count = 2;
};

/// A mesh boundary edge as a master edge (2 nodes for order 1, 3 for order 2).
MasterEdge to_master_edge(const core::BoundaryEdge& be, int order);

/// The closest point of a master surface to a slave point.
struct SegmentProjection {
  bool found = false;
  int edge = -1;           ///< index into the search's edges
  int vertex = -1;         ///< master node when the closest point is an edge end, else -1
  double xi = 0.0;         ///< edge parameter in [0, 1]
  double gap = 0.0;
  Vec2 normal = Vec2::Zero();
  Vec2 point = Vec2::Zero();
  std::array<double, 3> weights{0, 0, 0};  ///< shape function values at xi
  /// The closest point is a free end of the master surface and p lies beyond the rounded end
  /// (see MasterSurfaceSearch): p faces no master.
  bool beyond_free_end = false;
  /// Which function of the positions the gap is (MasterSurfaceSearch): the edge's own, the
  /// rounded free end, the distance from a vertex, or the vertex normal's projection.
  enum class Branch { kEdge, kRoundedEnd, kVertexOutside, kVertexInside };
  Branch branch = Branch::kEdge;
};

/// Edge shape functions on the parameter xi in [0, 1] (ends 0 and 1, middle node 2), with their
/// first and second derivatives.
void edge_shape(int count, double xi, std::array<double, 3>& n, std::array<double, 3>& dn,
                std::array<double, 3>& ddn);
/// Σ_a w_a x_a over the edge's nodes.
Vec2 combine(const MasterEdge& e, const std::vector<Vec2>& x, const std::array<double, 3>& w);

/// The unit normal (t_y, −t_x) of a tangent t: outward for an edge with its body on the left.
Vec2 outward_normal(const Vec2& tangent);
/// The outward unit normal of an edge at parameter xi.
Vec2 edge_normal(const MasterEdge& e, const std::vector<Vec2>& x, double xi);

/// Closest-point projection onto one linear or quadratic edge (Newton on the parameter,
/// clamped to the edge). The gap and normal are the edge's own (no vertex treatment).
SegmentProjection project_on_edge(const MasterEdge& edge, const std::vector<Vec2>& x,
                                  const Vec2& p);

/// Closest-point search over a master surface: a uniform bucket grid over the edges' bounding
/// boxes (grown by the search distance) gives the candidate edges of a point in O(1), so
/// detection costs O(n_slave + n_master), never their product.
///
/// A point whose closest point is an edge end (a slave facing a master corner or sliding from
/// one edge to the next) gets the vertex treatment: outside the body the normal is the
/// direction from the vertex to the point and the gap its distance (continuous with the
/// adjacent edges' gaps); inside, the normal is the mean of the adjacent edges' normals.
///
/// At a free end of the master surface (one adjacent edge) the surface continues, for a tenth
/// of the end edge's length, as a parabola tangent to the edge that falls away by that length:
/// gap = n·d + s²/band with s the distance past the end. A slave that sank just past the end of
/// a master (a block's corner on a block of the same width, which Poisson's effect pushes past
/// the end) is held, never released, and the gap is continuous, so the active set does not
/// cycle on it. Farther out, a point is beside the master (a slave beside a punch's corner is
/// not under it): its gap is its distance from the end, and it is flagged `beyond_free_end`.
class MasterSurfaceSearch {
 public:
  MasterSurfaceSearch(std::vector<MasterEdge> edges, const std::vector<Vec2>& x,
                      double search_distance);
  /// Projection of p; not found when no edge lies within the search distance. Edges that
  /// contain `exclude_node` are skipped (a slave node never contacts its own edges).
  SegmentProjection project(const Vec2& p, int exclude_node = -1) const;
  const std::vector<MasterEdge>& edges() const { return edges_; }
  /// The edges whose boxes, grown by the search distance, may overlap the box [lo, hi]
  /// (sorted, unique).
  std::vector<int> edges_near(const Vec2& lo, const Vec2& hi) const;
  /// The unit outward normal at a master node: the mean of its adjacent edges' normals at it.
  Vec2 vertex_normal(int node) const;
  /// The edges (indices into edges()) that meet at a master node.
  const std::vector<int>& vertex_edges(int node) const { return vertex_edges_[vertex_slot_[node]]; }
  /// Whether a master node ends the surface (one adjacent edge).
  bool is_free_end(int node) const;

 private:
  std::vector<MasterEdge> edges_;
  const std::vector<Vec2>& x_;
  double search_;
  Vec2 origin_ = Vec2::Zero();
  double cell_ = 1.0;
  int nx_ = 1, ny_ = 1;
  std::vector<std::vector<int>> cells_;
  std::vector<std::vector<int>> vertex_edges_;  ///< per master node: adjacent edges (by id map)
  std::vector<int> vertex_slot_;                ///< node -> row in vertex_edges_, -1 if none

  void cell_range(const Vec2& lo, const Vec2& hi, int& i0, int& i1, int& j0, int& j1) const;
  /// The vertex treatment of a closest point at an edge end (see the class comment).
  void treat_vertex(const Vec2& p, SegmentProjection& q) const;
};

/// A linearised gap row: δg = Σ_k c_k · δu_k over its nodes. A node-based row (node_to_segment,
/// node_to_node) has c = n at its slave node and −w_a n at the master nodes; a mortar row
/// integrates over the slave surface and is divided by its weight, so that every row's gap is a
/// length and its multiplier a force.
struct GapRow {
  int slave = -1;             ///< the node that owns the row (where its results are reported)
  std::vector<std::pair<int, Vec2>> terms;  ///< (node, c_k)
  Vec2 normal = Vec2::UnitY();///< the normal at the slave (for reports)
  double gap = 0.0;           ///< at the configuration it was detected in
  /// Mortar rows: ∫ Φ_j t ds, the share of the slave surface the row stands for, so that the
  /// row's force divided by it is the pressure at its node. 0 for node-based rows.
  double weight = 0.0;
  /// Finite strain: the Hessian ∂²g/∂x² over the terms' positions (2 per term, in terms
  /// order), for the contact's geometric stiffness −λ ∂²g in Newton. Empty: g is linear in u.
  Eigen::MatrixXd curvature;
  double penalty = 0.0;       ///< prescribed penalty (seed gap elements), 0 = method's choice
  int pair = 0;               ///< which [[contact]] entry produced it
  int slot = -1;              ///< stable identity across detections (see ContactPairs::num_slots)
};

/// A node-based row: slave node s, master nodes with weights, normal n: c_s = n, c_a = −w_a n.
GapRow node_row(int slave, const Vec2& normal, double gap,
                const std::vector<std::pair<int, double>>& master);

}  // namespace c2d::constraints
