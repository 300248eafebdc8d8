// SurfaceCondensation: K condensed onto its constraint rows solves the same systems as the
// assembled saddle point, for held rows (exact and compliant), rows whose force follows another
// row's (friction's slip rows) and free rows, on a supported and on a floating body (K singular,
// made definite by the regularising rows and cancelled exactly).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "constraints/surface_condensation.hpp"

using namespace c2d;
using namespace c2d::constraints;
using States = SurfaceCondensation::RowStates;

namespace {

/// A spring chain of n unknowns (grounded at the first unless `floating`).
SpMat chain(int n, bool floating) {
  std::vector<Triplet> t;
  for (int i = 0; i < n; ++i) {
    double d = 2.0;
    if (!floating && i == 0) d = 3.0;
    if (floating && (i == 0 || i + 1 == n)) d = 1.0;  // the Laplacian: constants are free
    t.emplace_back(i, i, d);
    if (i + 1 < n) t.emplace_back(i, i + 1, -1.0), t.emplace_back(i + 1, i, -1.0);
  }
  SpMat k(n, n);
  k.setFromTriplets(t.begin(), t.end());
  return k;
}

/// Cᵀ: `rows` random rows of 3 entries on the unknowns 0..touch−1 (the tail).
SpMat random_rows(int n, int rows, int touch, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> col(0, touch - 1);
  std::vector<Triplet> t;
  for (int r = 0; r < rows; ++r)
    for (int k = 0; k < 3; ++k) t.emplace_back(col(rng), r, u(rng));
  SpMat ct(n, rows);
  ct.setFromTriplets(t.begin(), t.end());
  return ct;
}

/// The assembled system in [u; w]: K u − Cᵀ w = f, each row's equation, dense LU.
void dense_reference(const SpMat& k, const SpMat& ct, const VecX& f, const States& st, VecX& u,
                     VecX& w) {
  const int n = static_cast<int>(k.rows()), rows = static_cast<int>(ct.cols());
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n + rows, n + rows);
  VecX b = VecX::Zero(n + rows);
  a.topLeftCorner(n, n) = Eigen::MatrixXd(k);
  a.topRightCorner(n, rows) = -Eigen::MatrixXd(ct);
  b.head(n) = f;
  for (int r = 0; r < rows; ++r) a(n + r, n + r) = 1.0;  // free: w_r = 0
  for (size_t h = 0; h < st.held.size(); ++h) {
    const int r = st.held[h];
    a.row(n + r).setZero();
    a.block(n + r, 0, 1, n) = Eigen::MatrixXd(ct.col(r)).transpose();
    a(n + r, n + r) = st.compliance[h];
    b[n + r] = st.target[h];
  }
  for (size_t k2 = 0; k2 < st.following.size(); ++k2) {
    const int r = st.following[k2];
    if (st.leader[k2] >= 0) a(n + r, n + st.leader[k2]) = -st.factor[k2];
    b[n + r] = st.offset[k2];
  }
  const VecX x = a.fullPivLu().solve(b);
  u = x.head(n);
  w = x.tail(rows);
}

/// Rows 0..3 equality-like (held), 4..11 "normal" (held or free), 12..19 "tangential" (held,
/// following their normal row, or free), as a frictional solve lays them out.
States mixed_states(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  States st;
  for (int j = 0; j < 4; ++j) st.hold(j, 0.0, u(rng));
  for (int i = 0; i < 8; ++i) {
    const bool closed = i % 4 != 3;
    if (closed) st.hold(4 + i, i % 2 ? 0.0 : 0.05, u(rng));
    if (i % 3 == 0) st.hold(12 + i, 0.0, u(rng));               // sticking
    else if (i % 3 == 1) st.follow(12 + i, closed ? 4 + i : -1, 0.1 * u(rng), 0.3);  // slipping
  }
  return st;
}

/// mixed_states moved onto the rows from `first` on (the rows before it free).
States shifted(States st, int first) {
  for (int& r : st.held) r += first;
  for (int& r : st.following) r += first;
  for (int& r : st.leader) r = r >= 0 ? r + first : r;
  return st;
}

/// Solves a random load with mixed_states on the rows from `first` on of `sc` (factorised) and
/// compares u, the rows' forces and the tail-only u with the assembled system's. Tolerance:
/// 1e-9 of the solution's largest entry (the chain's condition number is ~n² = 4e4 grounded, a
/// few times that floating).
void expect_assembled_solution(SurfaceCondensation& sc, const SpMat& k, const SpMat& ct,
                               std::mt19937& rng, int first = 0) {
  const int n = static_cast<int>(k.rows());
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const VecX f = VecX::NullaryExpr(n, [&] { return u(rng); });
  const States st = shifted(mixed_states(rng), first);
  VecX w, u_tail, u_full, u_ref, w_ref;
  double rcond = 0.0;
  ASSERT_EQ(sc.solve(f, st, w, u_tail, rcond), SolveStatus::kConverged) << sc.message();
  ASSERT_EQ(sc.complete(u_full), SolveStatus::kConverged);
  dense_reference(k, ct, f, st, u_ref, w_ref);
  const double scale = std::max(u_ref.cwiseAbs().maxCoeff(), w_ref.cwiseAbs().maxCoeff());
  ASSERT_EQ(w.size(), ct.cols());
  EXPECT_LT((u_full - u_ref).cwiseAbs().maxCoeff(), 1e-9 * scale);
  EXPECT_LT((w - w_ref).cwiseAbs().maxCoeff(), 1e-9 * scale);
  // On the unknowns the rows touch (the tail) the tail-only u is the whole u's; zero elsewhere.
  std::vector<char> touched(n, 0);
  for (int c = 0; c < ct.outerSize(); ++c)
    for (SpMat::InnerIterator it(ct, c); it; ++it) touched[it.row()] = 1;
  for (int d = 0; d < n; ++d)
    EXPECT_NEAR(u_tail[d], touched[d] ? u_ref[d] : 0.0, 1e-9 * scale) << d;
  EXPECT_GT(rcond, 1e-13);
}

/// A chain with random rows, solved with mixed states (expect_assembled_solution).
void expect_matches(bool floating, unsigned seed) {
  std::mt19937 rng(seed);
  const int n = 200, rows = 20;
  const SpMat k = chain(n, floating);
  const SpMat ct = random_rows(n, rows, 60, rng);
  SurfaceCondensation sc(ct, nullptr);
  ASSERT_TRUE(sc.fits());
  // R: the four held rows and two normal rows with their tangential rows (enough for the
  // chain's one rigid mode when floating).
  ASSERT_TRUE(sc.factorize(k, {0, 1, 2, 3, 4, 5, 12, 13})) << sc.message();
  expect_assembled_solution(sc, k, ct, rng);
}

}  // namespace

TEST(SurfaceCondensation, HeldFollowingAndFreeRowsMatchTheAssembledSystem) {
  for (unsigned seed : {1u, 2u, 3u}) expect_matches(false, seed);
}

TEST(SurfaceCondensation, FloatingBodyIsSolvedExactlyThroughItsRegularisingRows) {
  for (unsigned seed : {4u, 5u, 6u}) expect_matches(true, seed);
}

TEST(SurfaceCondensation, TwoFloatingBodiesAnchoredApartMatchTheAssembledSystem) {
  // Two floating chains (bodies) joined only by rows 4..19 (contact-like: two entries on each);
  // rows 0..3 (equality-like) on the first alone. With anchor rows each chain is its own block
  // of L₂₂, and the solution is still the assembled system's (tolerance as above).
  for (unsigned seed : {11u, 12u, 13u}) {
    std::mt19937 rng(seed);
    const int half = 100, n = 2 * half, rows = 20;
    std::vector<Triplet> t;
    for (const SpMat& c : {chain(half, true), chain(half, true)}) {
      const int at = t.empty() ? 0 : half;
      for (int j = 0; j < c.outerSize(); ++j)
        for (SpMat::InnerIterator it(c, j); it; ++it) t.emplace_back(at + it.row(), at + j, it.value());
    }
    SpMat k(n, n);
    k.setFromTriplets(t.begin(), t.end());
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::uniform_int_distribution<int> near(0, 29);
    std::vector<Triplet> c;
    for (int r = 0; r < rows; ++r) {
      c.emplace_back(near(rng), r, u(rng));
      c.emplace_back(near(rng), r, u(rng));
      c.emplace_back(r < 4 ? near(rng) : half + near(rng), r, u(rng));
      if (r >= 4) c.emplace_back(half + near(rng), r, u(rng));
    }
    SpMat ct(n, rows);
    ct.setFromTriplets(c.begin(), c.end());
    SurfaceCondensation sc(ct, nullptr);
    ASSERT_TRUE(sc.factorize(k, {0, 1, 2, 3}, true)) << sc.message();
    EXPECT_EQ(sc.tail_blocks(), 2);
    EXPECT_EQ(sc.rows(), rows);
    expect_assembled_solution(sc, k, ct, rng);
  }
}

TEST(SurfaceCondensation, RowsThatCannotHoldAFloatingBodyAreSingular) {
  // No row held: nothing holds the floating chain (the regularising rows cancel exactly).
  std::mt19937 rng(9);
  const int n = 50;
  const SpMat ct = random_rows(n, 4, 20, rng);
  SurfaceCondensation sc(ct, nullptr);
  ASSERT_TRUE(sc.factorize(chain(n, true), {0, 1}));
  States st;  // every row free
  VecX w, u;
  double rcond = 1.0;
  EXPECT_EQ(sc.solve(VecX::Ones(n), st, w, u, rcond), SolveStatus::kSingular);
  EXPECT_LT(rcond, 1e-13);
}

TEST(SurfaceCondensation, RegularisingRowsThatLeaveARigidModeAreRefused) {
  std::mt19937 rng(10);
  const int n = 50;
  SurfaceCondensation sc(random_rows(n, 4, 20, rng), nullptr);
  EXPECT_FALSE(sc.factorize(chain(n, true), {}));  // K alone: the chain floats
}

TEST(SurfaceCondensation, RowsAppendedToAFactorisedCondensationSolveOnItsFactor) {
  // A second caller's rows on the same K (ipopt's crossover on its dual's condensation): the
  // first caller's 20 rows, factorised with its R on a floating chain, then 20 rows of the
  // second's, each a multiple (0.3..3) of one of the first's or a random row on the unknowns
  // they touch. Solved with mixed states on the appended rows (the first's free) on the first
  // factor: the assembled system's solution (tolerance as above), and no new factorisation.
  for (unsigned seed : {21u, 22u, 23u}) {
    std::mt19937 rng(seed);
    const int n = 200, rows = 20;
    const SpMat k = chain(n, true);
    const SpMat first = random_rows(n, rows, 60, rng);
    std::vector<int> touched;
    for (int c = 0; c < first.outerSize(); ++c)
      for (SpMat::InnerIterator it(first, c); it; ++it) touched.push_back(static_cast<int>(it.row()));
    std::uniform_real_distribution<double> u(-1.0, 1.0), factor(0.3, 3.0);
    std::uniform_int_distribution<int> pick(0, static_cast<int>(touched.size()) - 1);
    std::vector<Triplet> t;
    for (int r = 0; r < rows; ++r) {
      if (r % 2 == 0) {
        const double a = factor(rng);
        for (SpMat::InnerIterator it(first, (r * 7) % rows); it; ++it)
          t.emplace_back(it.row(), r, a * it.value());
      } else {
        for (int e = 0; e < 3; ++e) t.emplace_back(touched[pick(rng)], r, u(rng));
      }
    }
    SpMat second(n, rows);
    second.setFromTriplets(t.begin(), t.end());
    SurfaceCondensation sc(first, nullptr);
    ASSERT_TRUE(sc.factorize(k, {0, 1, 2, 3})) << sc.message();
    ASSERT_EQ(sc.add_rows(second), rows);
    EXPECT_EQ(sc.rows(), 2 * rows);
    SpMat both(n, 2 * rows);
    both.leftCols(rows) = first;
    both.rightCols(rows) = second;
    expect_assembled_solution(sc, k, both, rng, rows);
    EXPECT_EQ(sc.report().numeric_factorizations, 1);
  }
}

TEST(SurfaceCondensation, RowsOffTheTailOrBesideAnchorsAreNotAppended) {
  std::mt19937 rng(24);
  const int n = 100;
  const SpMat k = chain(n, false);
  const SpMat ct = random_rows(n, 4, 20, rng);
  SpMat off(n, 1);  // unknown 90: outside the tail (the rows touch 0..19)
  off.insert(90, 0) = 1.0;
  SurfaceCondensation sc(ct, nullptr);
  EXPECT_EQ(sc.add_rows(ct), -1);  // nothing factorised yet
  ASSERT_TRUE(sc.factorize(k, {}));
  EXPECT_EQ(sc.add_rows(off), -1);
  EXPECT_EQ(sc.rows(), 4);
  SurfaceCondensation anchored(ct, nullptr);
  ASSERT_TRUE(anchored.factorize(k, {}, true));
  EXPECT_EQ(anchored.add_rows(ct), -1);  // anchor rows follow the caller's rows
}
