#include "core/fill_ordering.hpp"

#include <Eigen/CholmodSupport>

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace c2d::core {

namespace {

/// AMD on the corners' edge graph (CHOLMOD's symmetric lower pattern, sorted, each edge once),
/// corners numbered by `corner`.
std::vector<int> amd_corner_order(const Mesh& mesh, const std::vector<int>& corner, int nc) {
  std::vector<int> count(nc + 1, 0);
  for (const auto& e : mesh.elements)
    for (int k = 0; k < 3; ++k) ++count[std::min(corner[e[k]], corner[e[(k + 1) % 3]]) + 1];
  std::partial_sum(count.begin(), count.end(), count.begin());
  std::vector<int> rows(count.back());
  std::vector<int> next(count.begin(), count.end() - 1);
  for (const auto& e : mesh.elements)
    for (int k = 0; k < 3; ++k) {
      const int a = corner[e[k]], b = corner[e[(k + 1) % 3]];
      rows[next[std::min(a, b)]++] = std::max(a, b);
    }
  // An interior edge is listed by both its triangles: sort each column, keep one of each.
  int out = 0;
  for (int j = 0; j < nc; ++j) {
    const auto begin = rows.begin() + count[j], end = rows.begin() + count[j + 1];
    std::sort(begin, end);
    const int start = out;
    for (auto it = begin; it != end; ++it)
      if (it == begin || *it != *(it - 1)) rows[out++] = *it;
    count[j] = start;
  }
  count[nc] = out;
  rows.resize(out);
  std::vector<double> ones(out, 1.0);  // AMD reads the pattern only
  Eigen::Map<SpMat> pattern(nc, nc, out, count.data(), rows.data(), ones.data());
  cholmod_sparse g = Eigen::viewAsCholmod(Eigen::Ref<SpMat>(pattern));
  g.stype = -1;
  cholmod_common c;
  cholmod_start(&c);
  c.print = 0;
  std::vector<int> order(nc);
  const int ok = cholmod_amd(&g, nullptr, 0, order.data(), &c);
  cholmod_finish(&c);
  if (!ok) throw std::runtime_error("AMD failed on the mesh's corner graph (out of memory?)");
  return order;
}

}  // namespace

std::vector<int> corner_graph_ordering(const Mesh& mesh, const DofMap& dofs) {
  if (mesh.elements.empty()) return {};
  const int nn = mesh.num_nodes();
  std::vector<int> corner(nn, -1);
  int nc = 0;
  for (const auto& e : mesh.elements)
    for (int k = 0; k < 3; ++k)
      if (corner[e[k]] < 0) corner[e[k]] = nc++;
  const std::vector<int> order = amd_corner_order(mesh, corner, nc);
  std::vector<int> position(nc);
  for (int k = 0; k < nc; ++k) position[order[k]] = k;
  // Sort key: corner at 2 p, mid-side right after its edge's first-ordered corner at 2 p + 1,
  // every other node last.
  const long last = 2L * nc;
  std::vector<long> key(nn, last);
  for (const auto& e : mesh.elements)
    for (int k = 0; k < 3; ++k) {
      const int pa = position[corner[e[k]]], pb = position[corner[e[(k + 1) % 3]]];
      key[e[k]] = 2L * pa;
      if (mesh.order == 2) key[e[3 + k]] = 2L * std::min(pa, pb) + 1;
    }
  std::vector<int> nodes(nn);
  std::iota(nodes.begin(), nodes.end(), 0);
  std::stable_sort(nodes.begin(), nodes.end(), [&](int a, int b) { return key[a] < key[b]; });
  std::vector<int> perm;
  perm.reserve(dofs.num_free());
  auto add = [&](int dof) {
    if (const int q = dofs.equation(dof); q >= 0) perm.push_back(q);
  };
  for (int v : nodes)
    for (int d = 0; d < 2; ++d) add(2 * v + d);
  for (int dof = 2 * nn; dof < dofs.num_dofs(); ++dof) add(dof);
  if (static_cast<int>(perm.size()) != dofs.num_free())
    throw std::logic_error("corner_graph_ordering: the permutation misses free DOFs");
  return perm;
}

}  // namespace c2d::core
