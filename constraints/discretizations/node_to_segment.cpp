#include "constraints/discretizations/node_to_segment.hpp"

#include <algorithm>

#include "core/mesh.hpp"

namespace c2d::constraints {

NodeToSegment::NodeToSegment(const DiscretizationInput& in)
    : slaves_(core::select_nodes(in.model, in.pair.slave)), index_(in.index) {
  const core::Mesh& mesh = in.model.mesh;
  if (in.pair.obstacle >= 0) {
    obstacle_index_ = in.pair.obstacle;
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
}

void NodeToSegment::detect(const std::vector<Vec2>& x, int first_slot,
                           std::vector<GapRow>& rows) const {
  if (obstacle_) {
    for (size_t k = 0; k < slaves_.size(); ++k) {
      const int s = slaves_[k];
      GapRow r;
      r.slave = s;
      obstacle_->gap(x[s], r.gap, r.normal);
      if (r.gap > search_) continue;
      r.master_id = obstacle_index_;
      r.pair = index_;
      r.slot = first_slot + static_cast<int>(k);
      rows.push_back(r);
    }
    return;
  }
  const MasterSurfaceSearch search(master_edges_, x, search_);
  for (size_t k = 0; k < slaves_.size(); ++k) {
    const int s = slaves_[k];
    const SegmentProjection q = search.project(x[s], s);
    if (!q.found) continue;
    GapRow r;
    r.slave = s;
    r.gap = q.gap;
    r.normal = q.normal;
    r.pair = index_;
    r.slot = first_slot + static_cast<int>(k);
    r.master_id = q.vertex >= 0 ? -2 - q.vertex : q.edge;
    const MasterEdge& e = master_edges_[q.edge];
    for (int a = 0; a < e.count; ++a)
      if (q.weights[a] != 0.0) r.master.emplace_back(e.nodes[a], q.weights[a]);
    rows.push_back(r);
  }
}

}  // namespace c2d::constraints
