#include "constraints/discretizations/node_to_segment.hpp"

#include <algorithm>

#include "constraints/gap_linearisation.hpp"
#include "core/mesh.hpp"

namespace c2d::constraints {

NodeToSegment::NodeToSegment(const DiscretizationInput& in)
    : slaves_(on_boundary(in.model.mesh, core::select_nodes(in.model, in.pair.slave))),
      index_(in.index) {
  const core::Mesh& mesh = in.model.mesh;
  if (in.pair.obstacle >= 0) {
    obstacle_ = &in.obstacles[in.pair.obstacle];
    if (in.pair.search_distance > 0) search_ = in.pair.search_distance;
    return;
  }
  for (int id : core::select_edges(in.model, *in.pair.master))
    master_edges_.push_back(to_master_edge(mesh.boundary_edges[id], mesh.order));
  double longest = 0.0;
  for (const auto& e : master_edges_)
    longest = std::max(longest, (mesh.nodes[e.nodes[1]] - mesh.nodes[e.nodes[0]]).norm());
  search_ = in.pair.search_distance > 0 ? in.pair.search_distance : 2.0 * longest;
  reference_x_ = &mesh.nodes;
  reference_.emplace(master_edges_, mesh.nodes, search_);
}

void NodeToSegment::detect_obstacle(const Configuration& c, int first_slot,
                                    std::vector<GapRow>& rows) const {
  for (size_t k = 0; k < slaves_.size(); ++k) {
    const int s = slaves_[k];
    double g;
    Vec2 n;
    if (c.small_strain) {  // the gap linearised about the reference position
      obstacle_->gap(c.reference[s], g, n);
      g += n.dot(c.x[s] - c.reference[s]);
    } else {
      obstacle_->gap(c.x[s], g, n);
    }
    if (g > search_) continue;
    GapRow r = node_row(s, n, g, {});
    if (!c.small_strain)
      set_row_derivatives(obstacle_gap(*obstacle_, s, c.positions(), c.curvature), r);
    r.pair = index_;
    r.slot = first_slot + static_cast<int>(k);
    rows.push_back(r);
  }
}

Vec2 NodeToSegment::reference_normal(const SegmentProjection& q) const {
  const MasterEdge& e = master_edges_[q.edge];
  if (q.vertex < 0 || reference_->is_free_end(q.vertex)) return edge_normal(e, *reference_x_, q.xi);
  return reference_->vertex_normal(q.vertex);
}

void NodeToSegment::detect(const Configuration& c, int first_slot,
                           std::vector<GapRow>& rows) const {
  if (obstacle_) return detect_obstacle(c, first_slot, rows);
  const MasterSurfaceSearch search(master_edges_, c.x, search_);
  for (size_t k = 0; k < slaves_.size(); ++k) {
    const int s = slaves_[k];
    const SegmentProjection q = search.project(c.x[s], s);
    if (!q.found) continue;
    const MasterEdge& e = master_edges_[q.edge];
    std::vector<std::pair<int, double>> master;
    for (int a = 0; a < e.count; ++a) master.emplace_back(e.nodes[a], q.weights[a]);
    Vec2 n = q.normal;
    double g = q.gap;
    if (c.small_strain && !q.beyond_free_end) {
      n = reference_normal(q);
      g = n.dot(c.x[s] - combine(e, c.x, q.weights));
    }
    GapRow r = node_row(s, n, g, master);
    // Finite strain: the exact gradient of the gap (it differs from the rows of node_row at
    // vertices, where the normal depends on the master's nodes) and its Hessian.
    if (!c.small_strain)
      set_row_derivatives(node_segment_gap(search, q, s, c.positions(), c.curvature), r);
    r.pair = index_;
    r.slot = first_slot + static_cast<int>(k);
    rows.push_back(r);
  }
}

}  // namespace c2d::constraints
