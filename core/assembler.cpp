#include "core/assembler.hpp"

#include <algorithm>

namespace c2d::core {

Assembler::Assembler(const Mesh& mesh, const DofMap& dofs) : mesh_(mesh), dofs_(dofs) {
  const int ndofe = 2 * mesh.nodes_per_element();
  std::vector<Triplet> pattern;
  pattern.reserve(static_cast<size_t>(mesh.num_elements()) * ndofe * ndofe);
  std::array<int, kMaxElementDofs> gd;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    element_dofs(e, gd);
    for (int a = 0; a < ndofe; ++a) {
      const int i = dofs.equation(gd[a]);
      if (i < 0) continue;
      for (int b = 0; b < ndofe; ++b) {
        const int j = dofs.equation(gd[b]);
        if (j >= 0) pattern.emplace_back(i, j, 0.0);
      }
    }
  }
  k_ff_.resize(dofs.num_free(), dofs.num_free());
  k_ff_.setFromTriplets(pattern.begin(), pattern.end());
  k_ff_.makeCompressed();

  scatter_.assign(static_cast<size_t>(mesh.num_elements()) * ndofe * ndofe, -1);
  const int* outer = k_ff_.outerIndexPtr();
  const int* inner = k_ff_.innerIndexPtr();
  for (int e = 0; e < mesh.num_elements(); ++e) {
    element_dofs(e, gd);
    int* s = &scatter_[static_cast<size_t>(e) * ndofe * ndofe];
    for (int b = 0; b < ndofe; ++b) {  // column-major local matrix
      const int j = dofs.equation(gd[b]);
      if (j < 0) continue;
      for (int a = 0; a < ndofe; ++a) {
        const int i = dofs.equation(gd[a]);
        if (i < 0) continue;
        const int* pos = std::lower_bound(inner + outer[j], inner + outer[j + 1], i);
        s[b * ndofe + a] = static_cast<int>(pos - inner);
      }
    }
  }
}

void Assembler::element_dofs(int e, std::array<int, kMaxElementDofs>& dofs) const {
  const int nn = mesh_.nodes_per_element();
  for (int i = 0; i < nn; ++i) {
    dofs[2 * i] = 2 * mesh_.elements[e][i];
    dofs[2 * i + 1] = 2 * mesh_.elements[e][i] + 1;
  }
}

void Assembler::assemble(const ElementMatrixFn& element_matrix, const VecX* u_full, VecX* lift) {
  const int ndofe = 2 * mesh_.nodes_per_element();
  double* values = k_ff_.valuePtr();
  std::fill(values, values + k_ff_.nonZeros(), 0.0);
  if (lift) lift->setZero(dofs_.num_free());
  LocalMatrix ke(ndofe, ndofe);
  std::array<int, kMaxElementDofs> gd;
  for (int e = 0; e < mesh_.num_elements(); ++e) {
    element_matrix(e, ke);
    const int* s = &scatter_[static_cast<size_t>(e) * ndofe * ndofe];
    for (int b = 0; b < ndofe; ++b)
      for (int a = 0; a < ndofe; ++a)
        if (s[b * ndofe + a] >= 0) values[s[b * ndofe + a]] += ke(a, b);
    if (lift && u_full) {
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
  }
}

}  // namespace c2d::core
