// Node-to-segment: each slave node projected onto the master surface (linear or quadratic
// boundary edges, bucket-grid search, vertex handling) or onto a rigid obstacle.
#pragma once

#include <optional>

#include "constraints/discretization.hpp"

namespace c2d::constraints {

class NodeToSegment final : public ContactDiscretization {
 public:
  explicit NodeToSegment(const DiscretizationInput& in);
  int num_slots() const override { return static_cast<int>(slaves_.size()); }
  const std::vector<int>& slave_nodes() const override { return slaves_; }
  void detect(const Configuration& c, int first_slot, std::vector<GapRow>& rows) const override;

 private:
  void detect_obstacle(const Configuration& c, int first_slot, std::vector<GapRow>& rows) const;
  /// Small strain: the normal of a projection found at the current positions, taken from the
  /// reference configuration (the edge's normal at the same parameter; at a vertex the mean of
  /// its edges'; at a free end its edge's).
  Vec2 reference_normal(const SegmentProjection& q) const;

  std::vector<int> slaves_;
  std::vector<MasterEdge> master_edges_;
  const std::vector<Vec2>* reference_x_ = nullptr;  ///< the mesh's node positions
  std::optional<MasterSurfaceSearch> reference_;  ///< the master surface in the reference configuration
  const Obstacle* obstacle_ = nullptr;
  double search_ = 1e300;
  int index_ = 0;
};

}  // namespace c2d::constraints
