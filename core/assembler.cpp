#include "core/assembler.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>

#include <omp.h>

namespace c2d::core {

namespace {

/// The elements around each node, in compressed rows: node v's are around[first[v]..first[v+1]).
void elements_around_nodes(const Mesh& mesh, std::vector<int>& first, std::vector<int>& around) {
  const int nn = mesh.nodes_per_element(), nv = mesh.num_nodes(), ne = mesh.num_elements();
  first.assign(nv + 1, 0);
  around.resize(static_cast<size_t>(ne) * nn);
  for (int e = 0; e < ne; ++e)
    for (int i = 0; i < nn; ++i) ++first[mesh.elements[e][i] + 1];
  for (int v = 0; v < nv; ++v) first[v + 1] += first[v];
  std::vector<int> fill(first.begin(), first.end() - 1);
  for (int e = 0; e < ne; ++e)
    for (int i = 0; i < nn; ++i) around[fill[mesh.elements[e][i]]++] = e;
}

}  // namespace

Assembler::Assembler(const Mesh& mesh, const DofMap& dofs) : mesh_(mesh), dofs_(dofs) {
  build_pattern();
  build_scatter();
  colour_chunks();
}

void Assembler::build_pattern() {
  const int nn = mesh_.nodes_per_element(), nv = mesh_.num_nodes();
  // The pattern from node adjacency, written straight into K_ff's compressed arrays: node v's
  // neighbours are the nodes of the elements around it (sorted, unique), and each free DOF of v
  // couples with the free DOFs of those nodes. Free DOFs are numbered in node order, so sorted
  // neighbours give sorted rows. (Triplets through setFromTriplets cost 5x more for T6.)
  std::vector<int> first, around;
  elements_around_nodes(mesh_, first, around);
  const int n = dofs_.num_free();
  std::vector<int> col_start(n + 1, -1), row_index;
  col_start[0] = 0;
  row_index.reserve(static_cast<size_t>(n) * (nn == 3 ? 14 : 26));
  std::vector<int> neighbours;
  for (int v = 0; v < nv; ++v) {
    neighbours.clear();
    for (int k = first[v]; k < first[v + 1]; ++k)
      for (int i = 0; i < nn; ++i) neighbours.push_back(mesh_.elements[around[k]][i]);
    std::sort(neighbours.begin(), neighbours.end());
    neighbours.erase(std::unique(neighbours.begin(), neighbours.end()), neighbours.end());
    for (int c = 0; c < 2; ++c) {
      const int j = dofs_.equation(2 * v + c);
      if (j < 0) continue;
      for (int w : neighbours)
        for (int cw = 0; cw < 2; ++cw)
          if (const int i = dofs_.equation(2 * w + cw); i >= 0) row_index.push_back(i);
      col_start[j + 1] = static_cast<int>(row_index.size());
    }
  }
  // Free DOFs on no element (a rigid plate's) have empty columns.
  for (int j = 0; j < n; ++j)
    if (col_start[j + 1] < 0) col_start[j + 1] = col_start[j];
  k_ff_.resize(n, n);
  k_ff_.resizeNonZeros(static_cast<Eigen::Index>(row_index.size()));
  std::copy(col_start.begin(), col_start.end(), k_ff_.outerIndexPtr());
  std::copy(row_index.begin(), row_index.end(), k_ff_.innerIndexPtr());
  std::fill(k_ff_.valuePtr(), k_ff_.valuePtr() + row_index.size(), 0.0);
}

void Assembler::build_scatter() {
  const int ndofe = 2 * mesh_.nodes_per_element();
  scatter_.assign(static_cast<size_t>(mesh_.num_elements()) * ndofe * ndofe, -1);
  const int* outer = k_ff_.outerIndexPtr();
  const int* inner = k_ff_.innerIndexPtr();
  // Each element's positions are its own: the searches run on every thread.
#pragma omp parallel for schedule(static) if (mesh_.num_elements() >= kMinParallelElements)
  for (int e = 0; e < mesh_.num_elements(); ++e) {
    std::array<int, kMaxElementDofs> gd;
    element_dofs(e, gd);
    int* s = &scatter_[static_cast<size_t>(e) * ndofe * ndofe];
    for (int b = 0; b < ndofe; ++b) {  // column-major local matrix
      const int j = dofs_.equation(gd[b]);
      if (j < 0) continue;
      for (int a = 0; a < ndofe; ++a) {
        const int i = dofs_.equation(gd[a]);
        if (i < 0) continue;
        const int* pos = std::lower_bound(inner + outer[j], inner + outer[j + 1], i);
        s[b * ndofe + a] = static_cast<int>(pos - inner);
      }
    }
  }
}

void Assembler::colour_chunks() {
  const int nn = mesh_.nodes_per_element(), ne = mesh_.num_elements();
  // Colour contiguous chunks of elements (mesh order is spatially coherent, so a chunk touches
  // few others and keeps its memory local): greedy, each chunk takes the first colour no chunk
  // sharing one of its nodes has. Chunks of one colour touch disjoint entries.
  const int chunk = std::max(64, ne / 256);
  std::vector<std::uint64_t> seen(mesh_.num_nodes(), 0);
  for (int first = 0; first < ne; first += chunk) {
    const int last = std::min(ne, first + chunk);
    std::uint64_t used = 0;
    for (int e = first; e < last; ++e)
      for (int i = 0; i < nn; ++i) used |= seen[mesh_.elements[e][i]];
    // 64 colours: a chunk's neighbours are few; should they all be taken, the chunk runs alone.
    const int c = ~used != 0 ? std::countr_one(used) : 64;
    if (c < 64)
      for (int e = first; e < last; ++e)
        for (int i = 0; i < nn; ++i) seen[mesh_.elements[e][i]] |= std::uint64_t{1} << c;
    if (c >= static_cast<int>(colours_.size())) colours_.resize(c + 1);
    colours_[c].push_back(first);
  }
  if (colours_.size() > 64) {  // lone chunks: one colour each
    const auto lone = colours_[64];
    colours_.resize(64);
    for (int first : lone) colours_.push_back({first});
  }
  chunk_ = chunk;
}

void Assembler::element_dofs(int e, std::array<int, kMaxElementDofs>& dofs) const {
  const int nn = mesh_.nodes_per_element();
  for (int i = 0; i < nn; ++i) {
    dofs[2 * i] = 2 * mesh_.elements[e][i];
    dofs[2 * i + 1] = 2 * mesh_.elements[e][i] + 1;
  }
}

void Assembler::set_threads(int threads) {
  threads_ = threads > 0 ? threads
             : mesh_.num_elements() >= kMinParallelElements ? omp_get_max_threads()
                                                            : 1;
}

void Assembler::add_element(int e, const LocalMatrix& ke, const VecX* u_full, VecX* lift) {
  const int ndofe = 2 * mesh_.nodes_per_element();
  double* values = k_ff_.valuePtr();
  const int* s = &scatter_[static_cast<size_t>(e) * ndofe * ndofe];
  for (int b = 0; b < ndofe; ++b)
    for (int a = 0; a < ndofe; ++a)
      if (s[b * ndofe + a] >= 0) values[s[b * ndofe + a]] += ke(a, b);
  if (!lift || !u_full) return;
  std::array<int, kMaxElementDofs> gd;
  element_dofs(e, gd);
  for (int b = 0; b < ndofe; ++b) {
    if (!dofs_.is_constrained(gd[b])) continue;
    const double ub = (*u_full)[gd[b]];
    if (ub == 0.0) continue;
    for (int a = 0; a < ndofe; ++a) {
      const int i = dofs_.equation(gd[a]);
      if (i >= 0) (*lift)[i] += ke(a, b) * ub;
    }
  }
}

void Assembler::assemble(const ElementMatrixFn& element_matrix, const VecX* u_full, VecX* lift) {
  const int ndofe = 2 * mesh_.nodes_per_element();
  std::fill(k_ff_.valuePtr(), k_ff_.valuePtr() + k_ff_.nonZeros(), 0.0);
  if (lift) lift->setZero(dofs_.num_free());
  // Chunks of one colour touch disjoint entries of K_ff and of the lift: no locks. Each entry
  // sums its elements colour after colour, in element order within a chunk, on one thread as on
  // several: K_ff does not depend on the thread count to the last bit.
  const int ne = mesh_.num_elements();
#pragma omp parallel num_threads(threads_)
  {
    LocalMatrix ke(ndofe, ndofe);
    for (const auto& colour : colours_) {
      const int n = static_cast<int>(colour.size());
#pragma omp for schedule(dynamic, 1)
      for (int k = 0; k < n; ++k)
        for (int e = colour[k]; e < std::min(ne, colour[k] + chunk_); ++e) {
          element_matrix(e, ke);
          add_element(e, ke, u_full, lift);
        }
    }
  }
}

}  // namespace c2d::core
