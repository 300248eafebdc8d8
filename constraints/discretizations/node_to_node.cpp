#include "constraints/discretizations/node_to_node.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "core/errors.hpp"
#include "core/mesh.hpp"

namespace c2d::constraints {

namespace {

/// The nearest of `masters` to each of `slaves` (itself excluded): a bucket grid searched in
/// square rings of cells; every node in ring r + 1 lies at least r cells away, so the search
/// stops once the best distance is within that. -1 where there is none.
std::vector<std::pair<int, double>> nearest_nodes(const std::vector<Vec2>& nodes,
                                                  const std::vector<int>& masters,
                                                  const std::vector<int>& slaves) {
  Vec2 lo = Vec2::Constant(1e300), hi = Vec2::Constant(-1e300);
  for (int n : masters) lo = lo.cwiseMin(nodes[n]), hi = hi.cwiseMax(nodes[n]);
  const double cell =
      std::max((hi - lo).norm() / std::sqrt(static_cast<double>(masters.size())), 1e-12);
  std::map<std::pair<long, long>, std::vector<int>> grid;
  auto key = [&](const Vec2& p) {
    return std::make_pair(static_cast<long>(std::floor((p.x() - lo.x()) / cell)),
                          static_cast<long>(std::floor((p.y() - lo.y()) / cell)));
  };
  for (int n : masters) grid[key(nodes[n])].push_back(n);
  std::vector<std::pair<int, double>> out;
  for (int s : slaves) {
    const auto [ci, cj] = key(nodes[s]);
    int best = -1;
    double best_d = 1e300;
    for (int ring = 0; ring <= 4096; ++ring) {
      for (long i = ci - ring; i <= ci + ring; ++i)
        for (long j = cj - ring; j <= cj + ring; ++j) {
          if (std::max(std::abs(i - ci), std::abs(j - cj)) != ring) continue;
          const auto it = grid.find({i, j});
          if (it == grid.end()) continue;
          for (int n : it->second) {
            const double d = (nodes[n] - nodes[s]).norm();
            if (n != s && d < best_d) best_d = d, best = n;
          }
        }
      if (best >= 0 && best_d <= ring * cell) break;
    }
    out.emplace_back(best, best_d);
  }
  return out;
}

}  // namespace

NodeToNode::NodeToNode(const DiscretizationInput& in) : index_(in.index) {
  const ContactPairSpec& cs = in.pair;
  const std::vector<Vec2>& nodes = in.model.mesh.nodes;
  slaves_ = on_boundary(in.model.mesh, core::select_nodes(in.model, cs.slave));
  const auto nearest = nearest_nodes(nodes, core::select_nodes(in.model, *cs.master), slaves_);
  for (size_t k = 0; k < slaves_.size(); ++k) {
    const int s = slaves_[k];
    const auto [best, best_d] = nearest[k];
    if (best < 0) throw InputError(cs.where + ": no master node for slave node " + std::to_string(s + 1));
    NodePair np;
    np.master = best;
    np.slave = s;
    if (cs.direction) {
      np.direction = *cs.direction;
    } else if (best_d > 0) {
      np.direction = (nodes[s] - nodes[best]) / best_d;
    } else {
      throw InputError(cs.where + ": slave node " + std::to_string(s + 1) +
                       " coincides with its master node; give 'direction = [nx, ny]'");
    }
    pairs_.push_back(np);
  }
}

NodeToNode::NodeToNode(std::vector<NodePair> pairs, int index)
    : pairs_(std::move(pairs)), index_(index) {
  for (const auto& np : pairs_) slaves_.push_back(np.slave);
}

void NodeToNode::detect(const Configuration& c, int first_slot,
                        std::vector<GapRow>& rows) const {
  // The direction is fixed, so the gap is linear in u in either configuration.
  for (size_t k = 0; k < pairs_.size(); ++k) {
    const NodePair& np = pairs_[k];
    GapRow r = node_row(np.slave, np.direction,
                        np.direction.dot(c.x[np.slave] - c.x[np.master]), {{np.master, 1.0}});
    r.penalty = np.penalty;
    r.pair = index_;
    r.slot = first_slot + static_cast<int>(k);
    rows.push_back(r);
  }
}

}  // namespace c2d::constraints
