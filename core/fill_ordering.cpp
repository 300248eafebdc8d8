#include "core/fill_ordering.hpp"

#include <Eigen/CholmodSupport>

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace c2d::core {

namespace {

/// The mesh's element corners, numbered 0 .. count−1 in order of first appearance.
struct Corners {
  std::vector<int> id;  ///< per node: its corner number, −1 for a mid-side or lone node
  int count = 0;
};

Corners number_corners(const Mesh& mesh) {
  Corners c{std::vector<int>(mesh.num_nodes(), -1), 0};
  for (const auto& e : mesh.elements)
    for (int k = 0; k < 3; ++k)
      if (c.id[e[k]] < 0) c.id[e[k]] = c.count++;
  return c;
}

/// The corners' edge graph as CHOLMOD's symmetric lower pattern (sorted, each edge once).
class CornerGraph {
 public:
  CornerGraph(const Mesh& mesh, const Corners& corners) : n_(corners.count), start_(n_ + 1, 0) {
    const auto& id = corners.id;
    for (const auto& e : mesh.elements)
      for (int k = 0; k < 3; ++k) ++start_[std::min(id[e[k]], id[e[(k + 1) % 3]]) + 1];
    std::partial_sum(start_.begin(), start_.end(), start_.begin());
    rows_.resize(start_.back());
    std::vector<int> next(start_.begin(), start_.end() - 1);
    for (const auto& e : mesh.elements)
      for (int k = 0; k < 3; ++k) {
        const int a = id[e[k]], b = id[e[(k + 1) % 3]];
        rows_[next[std::min(a, b)]++] = std::max(a, b);
      }
    // An interior edge is listed by both its triangles: sort each column, keep one of each.
    int out = 0;
    for (int j = 0; j < n_; ++j) {
      const auto begin = rows_.begin() + start_[j], end = rows_.begin() + start_[j + 1];
      std::sort(begin, end);
      const int first = out;
      for (auto it = begin; it != end; ++it)
        if (it == begin || *it != *(it - 1)) rows_[out++] = *it;
      start_[j] = first;
    }
    start_[n_] = out;
    rows_.resize(out);
    ones_.assign(out, 1.0);  // the orderings read the pattern only
    cholmod_start(&common_);
    common_.print = 0;
  }
  ~CornerGraph() { cholmod_finish(&common_); }
  CornerGraph(const CornerGraph&) = delete;
  CornerGraph& operator=(const CornerGraph&) = delete;

  /// AMD's elimination order of the corners.
  std::vector<int> amd() {
    std::vector<int> order(n_);
    cholmod_sparse g = view();
    if (!cholmod_amd(&g, nullptr, 0, order.data(), &common_))
      throw std::runtime_error("AMD failed on the mesh's corner graph (out of memory?)");
    return order;
  }
  /// METIS's vertex bisection: per corner 0, 1 or 2 (the separator); empty when it fails (no
  /// METIS in this CHOLMOD).
  std::vector<int> bisect() {
    std::vector<int> part(n_);
    cholmod_sparse g = view();
    if (cholmod_bisect(&g, nullptr, 0, 1, part.data(), &common_) < 0) return {};
    return part;
  }

 private:
  cholmod_sparse view() {
    Eigen::Map<SpMat> pattern(n_, n_, static_cast<Eigen::Index>(rows_.size()), start_.data(),
                              rows_.data(), ones_.data());
    cholmod_sparse g = Eigen::viewAsCholmod(Eigen::Ref<SpMat>(pattern));
    g.stype = -1;
    return g;
  }
  int n_;
  std::vector<int> start_, rows_;
  std::vector<double> ones_;
  cholmod_common common_;
};

/// The free DOFs node by node in the order of `nodes`, then the free DOFs beyond the nodes'.
std::vector<int> expand_to_dofs(const std::vector<int>& nodes, const DofMap& dofs) {
  std::vector<int> perm;
  perm.reserve(dofs.num_free());
  auto add = [&](int dof) {
    if (const int q = dofs.equation(dof); q >= 0) perm.push_back(q);
  };
  for (int v : nodes)
    for (int d = 0; d < 2; ++d) add(2 * v + d);
  for (int dof = 2 * static_cast<int>(nodes.size()); dof < dofs.num_dofs(); ++dof) add(dof);
  if (static_cast<int>(perm.size()) != dofs.num_free())
    throw std::logic_error("corner_graph_ordering: the permutation misses free DOFs");
  return perm;
}

std::vector<int> corner_order(const Mesh& mesh, const DofMap& dofs, const Corners& corners,
                              CornerGraph& graph) {
  const int nc = corners.count, nn = mesh.num_nodes();
  const std::vector<int> order = graph.amd();
  std::vector<int> position(nc);
  for (int k = 0; k < nc; ++k) position[order[k]] = k;
  // Sort key: corner at 2 p, mid-side right after its edge's first-ordered corner at 2 p + 1,
  // every other node last.
  const long last = 2L * nc;
  std::vector<long> key(nn, last);
  for (const auto& e : mesh.elements)
    for (int k = 0; k < 3; ++k) {
      const int pa = position[corners.id[e[k]]], pb = position[corners.id[e[(k + 1) % 3]]];
      key[e[k]] = 2L * pa;
      if (mesh.order == 2) key[e[3 + k]] = 2L * std::min(pa, pb) + 1;
    }
  std::vector<int> nodes(nn);
  std::iota(nodes.begin(), nodes.end(), 0);
  std::stable_sort(nodes.begin(), nodes.end(), [&](int a, int b) { return key[a] < key[b]; });
  return expand_to_dofs(nodes, dofs);
}

/// The free DOFs' parts from the corners' bisection (see mesh_fill_order); empty when a half
/// is empty.
std::vector<signed char> dof_parts(const Mesh& mesh, const DofMap& dofs, const Corners& corners,
                                   const std::vector<int>& corner_part) {
  std::vector<signed char> node_part(mesh.num_nodes(), 2);
  for (const auto& e : mesh.elements)
    for (int k = 0; k < 3; ++k) {
      const int a = corner_part[corners.id[e[k]]], b = corner_part[corners.id[e[(k + 1) % 3]]];
      node_part[e[k]] = static_cast<signed char>(a);
      // The edge's half (its corners are never in different halves), or the separator.
      if (mesh.order == 2) node_part[e[3 + k]] = static_cast<signed char>(a == 2 ? b : a);
    }
  std::vector<signed char> part(dofs.num_free(), 2);
  int count[3] = {0, 0, 0};
  for (int v = 0; v < mesh.num_nodes(); ++v)
    for (int d = 0; d < 2; ++d)
      if (const int q = dofs.equation(2 * v + d); q >= 0) part[q] = node_part[v];
  for (signed char p : part) ++count[static_cast<int>(p)];
  if (count[0] == 0 || count[1] == 0) return {};
  return part;
}

}  // namespace

std::vector<int> corner_graph_ordering(const Mesh& mesh, const DofMap& dofs) {
  if (mesh.elements.empty()) return {};
  const Corners corners = number_corners(mesh);
  CornerGraph graph(mesh, corners);
  return corner_order(mesh, dofs, corners, graph);
}

FillOrder mesh_fill_order(const Mesh& mesh, const DofMap& dofs, int min_split_unknowns) {
  FillOrder fill;
  if (mesh.elements.empty()) return fill;
  const Corners corners = number_corners(mesh);
  CornerGraph graph(mesh, corners);
  fill.order = corner_order(mesh, dofs, corners, graph);
  if (dofs.num_free() >= min_split_unknowns)
    if (const std::vector<int> corner_part = graph.bisect(); !corner_part.empty())
      fill.part = dof_parts(mesh, dofs, corners, corner_part);
  return fill;
}

}  // namespace c2d::core
