#include "core/mesh_refine.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>

namespace c2d::core {

namespace {

std::uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b));
  const auto hi = static_cast<std::uint64_t>(std::max(a, b));
  return lo << 32 | hi;
}

/// The mid-side node of every edge, made on first use; a segment's is made first and moved
/// onto the segment's curve, so the elements beside it share the projected node.
class Midpoints {
 public:
  Midpoints(CurveMesh& mesh, const CurveProjector& project) : mesh_(mesh) {
    map_.reserve(mesh.elements.size() * 2 + mesh.segments.size());
    for (const auto& s : mesh.segments) {
      const auto [node, made] = find(s[0], s[1]);
      if (made && project) project(s[2], mesh_.nodes[node]);
    }
  }
  int operator()(int a, int b) { return find(a, b).first; }

 private:
  std::pair<int, bool> find(int a, int b) {
    const auto [it, made] = map_.try_emplace(edge_key(a, b), static_cast<int>(mesh_.nodes.size()));
    if (made) {
      const Vec2 mid = 0.5 * (mesh_.nodes[a] + mesh_.nodes[b]);
      mesh_.nodes.push_back(mid);
    }
    return {it->second, made};
  }

  CurveMesh& mesh_;
  std::unordered_map<std::uint64_t, int> map_;
};

/// x's bits spread to the even positions of a 64-bit word (21 bits in, 42 out).
std::uint64_t spread_bits(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

}  // namespace

void subdivide(CurveMesh& mesh, const CurveProjector& project) {
  Midpoints mid(mesh, project);
  std::vector<std::array<int, 3>> segments;
  segments.reserve(2 * mesh.segments.size());
  for (const auto& s : mesh.segments) {
    const int m = mid(s[0], s[1]);
    segments.push_back({s[0], m, s[2]});
    segments.push_back({m, s[1], s[2]});
  }
  std::vector<std::array<int, 6>> elements;
  elements.reserve(4 * mesh.elements.size());
  for (const auto& e : mesh.elements) {
    const int a = e[0], b = e[1], c = e[2];
    const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
    // Each child keeps its parent's orientation.
    elements.push_back({a, ab, ca, -1, -1, -1});
    elements.push_back({ab, b, bc, -1, -1, -1});
    elements.push_back({ca, bc, c, -1, -1, -1});
    elements.push_back({ab, bc, ca, -1, -1, -1});
  }
  mesh.elements = std::move(elements);
  mesh.segments = std::move(segments);
}

void make_quadratic(CurveMesh& mesh, const CurveProjector& project) {
  Midpoints mid(mesh, project);
  for (auto& e : mesh.elements) {
    e[3] = mid(e[0], e[1]);
    e[4] = mid(e[1], e[2]);
    e[5] = mid(e[2], e[0]);
  }
  mesh.order = 2;
}

void renumber_spatially(CurveMesh& mesh) {
  const int n = static_cast<int>(mesh.nodes.size());
  if (n == 0) return;
  Vec2 lo = mesh.nodes[0], hi = mesh.nodes[0];
  for (const Vec2& p : mesh.nodes) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double extent = std::max((hi - lo).maxCoeff(), 1e-300);
  const double scale = static_cast<double>((1 << 21) - 1) / extent;
  std::vector<std::uint64_t> key(n);
  for (int i = 0; i < n; ++i) {
    const Vec2 q = (mesh.nodes[i] - lo) * scale;
    key[i] = spread_bits(static_cast<std::uint64_t>(q.x())) |
             spread_bits(static_cast<std::uint64_t>(q.y())) << 1;
  }
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key[a] < key[b]; });
  std::vector<int> renamed(n);
  std::vector<Vec2> nodes(n);
  for (int i = 0; i < n; ++i) {
    renamed[order[i]] = i;
    nodes[i] = mesh.nodes[order[i]];
  }
  mesh.nodes = std::move(nodes);
  const int nn = mesh.order == 1 ? 3 : 6;
  for (auto& e : mesh.elements)
    for (int i = 0; i < nn; ++i) e[i] = renamed[e[i]];
  for (auto& s : mesh.segments) s[0] = renamed[s[0]], s[1] = renamed[s[1]];
  std::stable_sort(mesh.elements.begin(), mesh.elements.end(), [](const auto& a, const auto& b) {
    return std::min({a[0], a[1], a[2]}) < std::min({b[0], b[1], b[2]});
  });
}

Mesh to_mesh(CurveMesh&& source, const std::vector<std::string>& curve_names) {
  Mesh mesh;
  mesh.order = source.order;
  mesh.nodes = std::move(source.nodes);
  mesh.elements = std::move(source.elements);
  mesh.element_body.assign(mesh.elements.size(), 0);
  mesh.element_material.assign(mesh.elements.size(), 0);
  mesh.orient_counter_clockwise();
  mesh.build_boundary();
  std::unordered_map<std::uint64_t, int> edge_index;
  edge_index.reserve(mesh.boundary_edges.size());
  for (size_t i = 0; i < mesh.boundary_edges.size(); ++i) {
    const auto& be = mesh.boundary_edges[i];
    edge_index[edge_key(be.nodes[0], be.nodes[1])] = static_cast<int>(i);
  }
  for (const auto& s : source.segments) {
    const auto it = edge_index.find(edge_key(s[0], s[1]));
    if (it != edge_index.end()) mesh.edge_groups[curve_names.at(s[2])].push_back(it->second);
  }
  for (auto& [name, ids] : mesh.edge_groups) {
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  }
  return mesh;
}

int subdivision_levels(double elements, double coarse_elements) {
  int levels = 0;
  while (levels < 8 && elements / std::pow(4.0, levels + 1) >= coarse_elements) ++levels;
  return levels;
}

}  // namespace c2d::core
