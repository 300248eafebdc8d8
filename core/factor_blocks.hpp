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

/// While it lives, OpenMP regions opened more than `levels` active levels below the calling
/// thread's current one run on that thread alone (it lowers OpenMP's max-active-levels, never
/// raises it, and restores it after; the setting is the calling task's own, so other threads
/// are not affected).
///
/// Why: CHOLMOD 3.0's supernodal factorisation opens, per supernode, OpenMP regions of a fixed
/// four threads (CHOLMOD_OMP_NUM_THREADS, set when the library was built) to clear and fill the
/// supernode; the num_threads clause overrides OMP_NUM_THREADS. Called from a one-thread
/// region, those regions are nested yet active, and libgomp creates their threads afresh each
/// time: on 2 cores a 105k-DOF split factorisation took 10-20x the default-threads time with
/// OMP_NUM_THREADS=1. With a one-thread budget, ActiveLevelCap(0) keeps CHOLMOD on one thread.
class ActiveLevelCap {
 public:
  explicit ActiveLevelCap(int levels);
  ~ActiveLevelCap();
  ActiveLevelCap(const ActiveLevelCap&) = delete;
  ActiveLevelCap& operator=(const ActiveLevelCap&) = delete;

 private:
  int saved_;
};

}  // namespace c2d::core
