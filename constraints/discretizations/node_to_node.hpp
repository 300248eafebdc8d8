// Node-to-node: fixed pairs of a slave and a master node with a fixed direction d, the gap
// g = d · (x_slave − x_master): each slave node with its nearest master node, or the seed's gap
// elements (with their own stiffness).
#pragma once

#include "constraints/discretization.hpp"

namespace c2d::constraints {

class NodeToNode final : public ContactDiscretization {
 public:
  /// A fixed pair; `penalty` > 0 is a stiffness the input prescribes.
  struct NodePair {
    int master = -1, slave = -1;
    Vec2 direction = Vec2::UnitY();
    double penalty = 0.0;
  };
  /// Each slave node of the pair with its nearest master node.
  explicit NodeToNode(const DiscretizationInput& in);
  /// Given pairs (the seed's gap elements), as pair `index`.
  NodeToNode(std::vector<NodePair> pairs, int index);
  int num_slots() const override { return static_cast<int>(pairs_.size()); }
  const std::vector<int>& slave_nodes() const override { return slaves_; }
  void detect(const Configuration& c, int first_slot, std::vector<GapRow>& rows) const override;

 private:
  std::vector<NodePair> pairs_;
  std::vector<int> slaves_;
  int index_ = 0;
};

}  // namespace c2d::constraints
