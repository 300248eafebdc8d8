#include "core/factor_blocks.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace c2d::core {

namespace {

/// Calls visit(column j, offset of L_jj in f.x) for the columns j < k.
template <class Visit>
void for_each_diagonal(const cholmod_factor& f, int k, Visit visit) {
  if (f.is_super) {
    const auto* super = static_cast<const int*>(f.super);
    const auto* pi = static_cast<const int*>(f.pi);
    const auto* px = static_cast<const int*>(f.px);
    for (size_t s = 0; s < f.nsuper && super[s] < k; ++s) {
      const int nsrow = pi[s + 1] - pi[s];
      for (int j = super[s]; j < std::min(super[s + 1], k); ++j)
        visit(static_cast<size_t>(px[s]) + static_cast<size_t>(j - super[s]) * (nsrow + 1));
    }
    return;
  }
  const auto* lp = static_cast<const int*>(f.p);
  for (int j = 0; j < k; ++j) visit(static_cast<size_t>(lp[j]));
}

}  // namespace

bool trailing_block(const cholmod_factor& f, int k0, Eigen::MatrixXd& l, VecX& pivots) {
  if (!f.x) return false;
  const int n = static_cast<int>(f.n), k = n - k0;
  l = Eigen::MatrixXd::Zero(k, k);
  pivots = VecX::Ones(k);
  const auto* x = static_cast<const double*>(f.x);
  if (f.is_super) {
    // Supernode s holds columns super[s] .. super[s+1]−1 as a dense column-major block whose
    // rows are s[pi[s]] .. s[pi[s+1]−1] (the supernode's own columns first).
    const auto* super = static_cast<const int*>(f.super);
    const auto* pi = static_cast<const int*>(f.pi);
    const auto* px = static_cast<const int*>(f.px);
    const auto* rows = static_cast<const int*>(f.s);
    for (size_t s = 0; s < f.nsuper; ++s) {
      const int c1 = super[s], c2 = super[s + 1];
      if (c2 <= k0) continue;
      const int nsrow = pi[s + 1] - pi[s];
      for (int j = std::max(c1, k0); j < c2; ++j)
        for (int r = 0; r < nsrow; ++r) {
          const int row = rows[pi[s] + r];
          if (row >= j)
            l(row - k0, j - k0) =
                x[static_cast<size_t>(px[s]) + r + static_cast<size_t>(j - c1) * nsrow];
        }
    }
    return true;
  }
  const auto* lp = static_cast<const int*>(f.p);
  const auto* li = static_cast<const int*>(f.i);
  const auto* lnz = static_cast<const int*>(f.nz);
  // Column j: the diagonal first (D_jj for L D Lᵀ, whose L has a unit diagonal), then below.
  for (int j = k0; j < n; ++j)
    for (int q = lp[j]; q < lp[j] + lnz[j]; ++q) l(li[q] - k0, j - k0) = x[q];
  if (!f.is_ll) {
    pivots = l.diagonal();
    l.diagonal().setOnes();
  }
  return true;
}

void diagonal_range(const cholmod_factor& f, int k, double& smallest, double& largest) {
  smallest = std::numeric_limits<double>::infinity();
  largest = 0;
  const auto* x = static_cast<const double*>(f.x);
  if (!x) return;
  for_each_diagonal(f, k, [&](size_t at) {
    const double d = std::abs(x[at]);
    smallest = std::min(smallest, d);
    largest = std::max(largest, d);
  });
}

cholmod_sparse lower_view(size_t n, size_t nnz, const int* start, const int* rows, const double* x) {
  cholmod_sparse a{};
  a.nrow = a.ncol = n;
  a.nzmax = nnz;
  a.p = const_cast<int*>(start);
  a.i = const_cast<int*>(rows);
  a.x = const_cast<double*>(x);
  a.stype = -1;
  a.itype = CHOLMOD_INT;
  a.xtype = CHOLMOD_REAL;
  a.dtype = CHOLMOD_DOUBLE;
  a.sorted = 1;
  a.packed = 1;
  return a;
}

cholmod_dense dense_view(const Eigen::MatrixXd& m) {
  cholmod_dense d{};
  d.nrow = d.d = static_cast<size_t>(m.rows());
  d.ncol = static_cast<size_t>(m.cols());
  d.nzmax = d.nrow * d.ncol;
  d.x = const_cast<double*>(m.data());
  d.xtype = CHOLMOD_REAL;
  d.dtype = CHOLMOD_DOUBLE;
  return d;
}

ActiveLevelCap::ActiveLevelCap(int levels) : saved_(omp_get_max_active_levels()) {
  omp_set_max_active_levels(std::min(saved_, omp_get_active_level() + std::max(levels, 0)));
}

ActiveLevelCap::~ActiveLevelCap() { omp_set_max_active_levels(saved_); }

}  // namespace c2d::core
