#include "core/fill_ordering.hpp"

#include <cholmod.h>

#include <algorithm>
#include <array>
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

/// A CHOLMOD workspace for one call.
struct Common {
  cholmod_common c{};
  Common() {
    cholmod_start(&c);
    c.print = 0;
  }
  ~Common() { cholmod_finish(&c); }
  Common(const Common&) = delete;
  Common& operator=(const Common&) = delete;
};

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

/// The corners' edge graph as CHOLMOD's symmetric lower pattern (sorted, each edge once), and
/// what expands a corner order to the free DOFs: each node's free equations and, for a T6
/// mid-side node, its edge's two corners.
class CornerGraph {
 public:
  CornerGraph(const Mesh& mesh, const DofMap& dofs, const Corners& corners)
      : n_(corners.count),
        start_(n_ + 1, 0),
        corner_(corners.id),
        edge_(mesh.num_nodes(), {-1, -1}),
        equations_(mesh.num_nodes(), {-1, -1}),
        num_free_(dofs.num_free()) {
    const auto& id = corners.id;
    for (const auto& e : mesh.elements)
      for (int k = 0; k < 3; ++k) {
        ++start_[std::min(id[e[k]], id[e[(k + 1) % 3]]) + 1];
        if (mesh.order == 2) edge_[e[3 + k]] = {id[e[k]], id[e[(k + 1) % 3]]};
      }
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
    for (int v = 0; v < mesh.num_nodes(); ++v)
      for (int d = 0; d < 2; ++d) equations_[v][d] = dofs.equation(2 * v + d);
    for (int dof = 2 * mesh.num_nodes(); dof < dofs.num_dofs(); ++dof)
      if (const int q = dofs.equation(dof); q >= 0) beyond_.push_back(q);
  }

  /// AMD's elimination order of the corners.
  std::vector<int> amd() const {
    std::vector<int> order(n_);
    Common common;
    cholmod_sparse g = view();
    if (!cholmod_amd(&g, nullptr, 0, order.data(), &common.c))
      throw std::runtime_error("AMD failed on the mesh's corner graph (out of memory?)");
    return order;
  }
  /// CAMD's elimination order of the corners, those with `last[c]` set after all others.
  std::vector<int> camd(std::vector<int> last) const {
    std::vector<int> order(n_);
    Common common;
    cholmod_sparse g = view();
    if (!cholmod_camd(&g, nullptr, 0, last.data(), order.data(), &common.c))
      throw std::runtime_error("CAMD failed on the mesh's corner graph (out of memory?)");
    return order;
  }
  /// METIS's vertex bisection: per corner 0, 1 or 2 (the separator); empty when it fails (no
  /// METIS in this CHOLMOD).
  std::vector<int> bisect() const {
    std::vector<int> part(n_);
    Common common;
    cholmod_sparse g = view();
    if (cholmod_bisect(&g, nullptr, 0, 1, part.data(), &common.c) < 0) return {};
    return part;
  }

  /// The free DOFs for an elimination order of the corners: node by node, each corner in its
  /// place, each T6 mid-side node right after its edge's first-ordered corner, other nodes
  /// last; then the free DOFs beyond the nodes'.
  std::vector<int> expand(const std::vector<int>& corner_order) const {
    const int nn = static_cast<int>(corner_.size());
    std::vector<long> position(n_);
    for (int k = 0; k < n_; ++k) position[corner_order[k]] = k;
    const long last = 2L * n_;
    std::vector<long> key(nn, last);
    for (int v = 0; v < nn; ++v) {
      if (corner_[v] >= 0)
        key[v] = 2 * position[corner_[v]];
      else if (edge_[v][0] >= 0)
        key[v] = 2 * std::min(position[edge_[v][0]], position[edge_[v][1]]) + 1;
    }
    std::vector<int> nodes(nn);
    std::iota(nodes.begin(), nodes.end(), 0);
    std::stable_sort(nodes.begin(), nodes.end(), [&](int a, int b) { return key[a] < key[b]; });
    std::vector<int> perm;
    perm.reserve(num_free_);
    for (int v : nodes)
      for (int q : equations_[v])
        if (q >= 0) perm.push_back(q);
    perm.insert(perm.end(), beyond_.begin(), beyond_.end());
    if (static_cast<int>(perm.size()) != num_free_)
      throw std::logic_error("corner_graph_ordering: the permutation misses free DOFs");
    return perm;
  }

  /// Per corner: 1 if a free DOF of its node is marked in `dof_marked`, else 0.
  std::vector<int> marked_corners(const std::vector<char>& dof_marked) const {
    std::vector<int> marked(n_, 0);
    for (size_t v = 0; v < corner_.size(); ++v)
      if (corner_[v] >= 0)
        for (int q : equations_[v])
          if (q >= 0 && dof_marked[q]) marked[corner_[v]] = 1;
    return marked;
  }

 private:
  cholmod_sparse view() const {
    cholmod_sparse g{};
    g.nrow = g.ncol = static_cast<size_t>(n_);
    g.nzmax = rows_.size();
    g.p = const_cast<int*>(start_.data());
    g.i = const_cast<int*>(rows_.data());
    g.stype = -1;
    g.itype = CHOLMOD_INT;
    g.xtype = CHOLMOD_PATTERN;
    g.dtype = CHOLMOD_DOUBLE;
    g.sorted = 1;
    g.packed = 1;
    return g;
  }
  int n_;
  std::vector<int> start_, rows_;
  std::vector<int> corner_;                    ///< per node: its corner, −1 if none
  std::vector<std::array<int, 2>> edge_;       ///< per T6 mid-side node: its edge's corners
  std::vector<std::array<int, 2>> equations_;  ///< per node: its two equations (−1: none)
  std::vector<int> beyond_;                    ///< free equations beyond the nodes'
  int num_free_;
};

namespace {

/// Per free DOF (of `n`): 1 in `tail`, else 0.
std::vector<char> tail_marks(int n, const std::vector<int>& tail) {
  std::vector<char> in_tail(n, 0);
  for (int q : tail) in_tail[q] = 1;
  return in_tail;
}

/// `perm` with the marked DOFs moved last, both parts in their relative order.
std::vector<int> marked_last(std::vector<int> perm, const std::vector<char>& in_tail) {
  std::stable_partition(perm.begin(), perm.end(), [&](int q) { return !in_tail[q]; });
  return perm;
}

}  // namespace

std::vector<int> FillOrder::moved_last(const std::vector<int>& tail) const {
  return marked_last(order, tail_marks(static_cast<int>(order.size()), tail));
}

std::vector<int> FillOrder::tail_last(const std::vector<int>& tail) const {
  if (!graph) return {};
  const std::vector<char> in_tail = tail_marks(static_cast<int>(order.size()), tail);
  return marked_last(graph->expand(graph->camd(graph->marked_corners(in_tail))), in_tail);
}

std::vector<int> corner_graph_ordering(const Mesh& mesh, const DofMap& dofs) {
  if (mesh.elements.empty()) return {};
  const CornerGraph graph(mesh, dofs, number_corners(mesh));
  return graph.expand(graph.amd());
}

FillOrder mesh_fill_order(const Mesh& mesh, const DofMap& dofs, int min_split_unknowns) {
  FillOrder fill;
  if (mesh.elements.empty()) return fill;
  const Corners corners = number_corners(mesh);
  auto graph = std::make_shared<const CornerGraph>(mesh, dofs, corners);
  fill.order = graph->expand(graph->amd());
  if (dofs.num_free() >= min_split_unknowns)
    if (const std::vector<int> corner_part = graph->bisect(); !corner_part.empty())
      fill.part = dof_parts(mesh, dofs, corners, corner_part);
  fill.graph = std::move(graph);
  return fill;
}

}  // namespace c2d::core
