// Node-to-segment: each slave node projected onto the master surface (linear or quadratic
// boundary edges, bucket-grid search, vertex handling) or onto a rigid obstacle.
#pragma once

#include "constraints/discretization.hpp"

namespace c2d::constraints {

class NodeToSegment final : public ContactDiscretization {
 public:
  explicit NodeToSegment(const DiscretizationInput& in);
  int num_slots() const override { return static_cast<int>(slaves_.size()); }
  const std::vector<int>& slave_nodes() const override { return slaves_; }
  void detect(const std::vector<Vec2>& x, int first_slot, std::vector<GapRow>& rows) const override;

 private:
  std::vector<int> slaves_;
  std::vector<MasterEdge> master_edges_;
  const Obstacle* obstacle_ = nullptr;
  int obstacle_index_ = -1;
  double search_ = 1e300;
  int index_ = 0;
};

}  // namespace c2d::constraints
