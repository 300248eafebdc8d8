// Dense pieces read out of a CHOLMOD factor, shared by TailCholesky and SplitCholesky.
#pragma once

#include <cholmod.h>

#include <Eigen/Dense>

#include "core/types.hpp"

namespace c2d::core {

/// L's trailing block, rows and columns k0 .. n−1 of the factor's order, dense with the lower
/// triangle filled. For a supernodal L Lᵀ factor `pivots` are ones; for a simplicial L D Lᵀ
/// factor L has a unit diagonal and `pivots` holds D's entries. False when the factor holds no
/// numbers.
bool trailing_block(const cholmod_factor& f, int k0, Eigen::MatrixXd& l, VecX& pivots);

/// The smallest and largest |L_jj| (|D_jj| for an L D Lᵀ factor) over the columns before k.
void diagonal_range(const cholmod_factor& f, int k, double& smallest, double& largest);

/// A CHOLMOD view of a symmetric matrix's lower triangle in compressed columns (n × n, nnz
/// entries, rows sorted within each column; no copy).
cholmod_sparse lower_view(size_t n, size_t nnz, const int* start, const int* rows, const double* x);

/// A CHOLMOD dense view of `m` (column-major, no copy).
cholmod_dense dense_view(const Eigen::MatrixXd& m);

}  // namespace c2d::core
