// core::TailCholesky (issue 19, item 1): the factor with a chosen tail ordered last. Against
// dense linear algebra on a 5-point Laplacian (plus a shift) of a 24 × 24 grid, 576 unknowns,
// the tail one edge of the grid (24 unknowns):
//  - L₂₂ D₂ L₂₂ᵀ equals the tail's Schur complement K_TT − K_TI K_II⁻¹ K_IT (1e-12 relative);
//  - forward then backward solves K x = b (relative residual 1e-13), also for a symmetric
//    indefinite K (the simplicial L D Lᵀ factor);
//  - a right-hand side on the tail stays on the tail through the forward substitution (the
//    other entries exactly zero) and equals D₂⁻¹ L₂₂⁻¹ b_T there;
//  - a matrix with a zero pivot is reported singular;
//  - factors sharing TailAnalyses analyse once per pattern and tail, and solve as precisely.
// The first two hold for CHOLMOD's CAMD order and for a given order with the tail moved last
// (set_ordering; here the unknowns in reverse, which no fill-reducing method would choose).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <vector>

#include "core/tail_cholesky.hpp"

using namespace c2d;

namespace {

constexpr int kSide = 24;

SpMat laplacian(double shift) {
  const int n = kSide * kSide;
  std::vector<Triplet> t;
  auto id = [](int i, int j) { return i * kSide + j; };
  for (int i = 0; i < kSide; ++i)
    for (int j = 0; j < kSide; ++j) {
      t.emplace_back(id(i, j), id(i, j), 4.0 + shift);
      if (i > 0) t.emplace_back(id(i, j), id(i - 1, j), -1.0);
      if (i + 1 < kSide) t.emplace_back(id(i, j), id(i + 1, j), -1.0);
      if (j > 0) t.emplace_back(id(i, j), id(i, j - 1), -1.0);
      if (j + 1 < kSide) t.emplace_back(id(i, j), id(i, j + 1), -1.0);
    }
  SpMat k(n, n);
  k.setFromTriplets(t.begin(), t.end());
  return k;
}

std::vector<int> edge() {
  std::vector<int> tail;
  for (int j = 0; j < kSide; ++j) tail.push_back((kSide - 1) * kSide + j);  // the top row
  return tail;
}

/// Parameter: whether the factor takes a given order (the unknowns reversed) instead of CAMD.
class TailOrder : public ::testing::TestWithParam<bool> {
 protected:
  void order(core::TailCholesky& f) {
    if (!GetParam()) return;
    if (!reversed_) {  // one order for every factor of the test, as a model has one
      std::vector<int> reversed(kSide * kSide);
      for (int k = 0; k < kSide * kSide; ++k) reversed[k] = kSide * kSide - 1 - k;
      reversed_ = std::make_shared<const core::FillOrder>(core::FillOrder{reversed, {}, {}});
    }
    f.set_ordering(reversed_);
  }
  std::shared_ptr<const core::FillOrder> reversed_;
};

}  // namespace

TEST_P(TailOrder, TailFactorIsTheCholeskyFactorOfTheSchurComplement) {
  const SpMat k = laplacian(0.01);
  const std::vector<int> tail = edge();
  core::TailCholesky f;
  order(f);
  ASSERT_EQ(f.factorize(k, tail), SolveStatus::kConverged) << f.report().message;
  EXPECT_EQ(f.report().ordering, GetParam() ? "given_tail_last" : "camd");
  ASSERT_EQ(f.tail_size(), kSide);
  // Dense Schur complement in the tail's order.
  const int n = static_cast<int>(k.rows()), t = f.tail_size();
  const Eigen::MatrixXd kd = Eigen::MatrixXd(k);
  std::vector<int> interior;
  for (int d = 0; d < n; ++d)
    if (f.tail_position()[d] < 0) interior.push_back(d);
  std::vector<int> order(t);
  for (int d : tail) order[f.tail_position()[d]] = d;
  Eigen::MatrixXd kii(interior.size(), interior.size()), kit(interior.size(), t), ktt(t, t);
  for (size_t a = 0; a < interior.size(); ++a) {
    for (size_t b = 0; b < interior.size(); ++b) kii(a, b) = kd(interior[a], interior[b]);
    for (int b = 0; b < t; ++b) kit(a, b) = kd(interior[a], order[b]);
  }
  for (int a = 0; a < t; ++a)
    for (int b = 0; b < t; ++b) ktt(a, b) = kd(order[a], order[b]);
  const Eigen::MatrixXd schur = ktt - kit.transpose() * kii.llt().solve(kit);
  const Eigen::MatrixXd l22 = f.tail_factor().triangularView<Eigen::Lower>();
  EXPECT_LT((l22 * f.tail_pivots().asDiagonal() * l22.transpose() - schur).norm(),
            1e-12 * schur.norm());
}

TEST_P(TailOrder, ForwardThenBackwardSolvesAndTailVectorsStayOnTheTail) {
  const SpMat k = laplacian(0.01);
  const std::vector<int> tail = edge();
  core::TailCholesky f;
  order(f);
  ASSERT_EQ(f.factorize(k, tail), SolveStatus::kConverged) << f.report().message;
  const int n = static_cast<int>(k.rows()), t = f.tail_size();
  VecX b(n);
  for (int i = 0; i < n; ++i) b[i] = std::sin(0.37 * i) + 0.1;
  VecX w, x;
  ASSERT_EQ(f.forward(b, w), SolveStatus::kConverged);
  ASSERT_EQ(f.backward(w, x), SolveStatus::kConverged);
  EXPECT_LT((k * x - b).norm(), 1e-13 * b.norm());
  // A vector on the tail: zero before the last t entries, L₂₂⁻¹ b_T in them.
  VecX bt = VecX::Zero(n), b2(t);
  for (int d : tail) {
    bt[d] = 1.0 + 0.5 * d / n;
    b2[f.tail_position()[d]] = bt[d];
  }
  ASSERT_EQ(f.forward(bt, w), SolveStatus::kConverged);
  EXPECT_EQ(w.head(n - t).cwiseAbs().maxCoeff(), 0.0);
  const VecX expect = VecX(f.tail_factor().triangularView<Eigen::Lower>().solve(b2))
                          .cwiseQuotient(f.tail_pivots());
  EXPECT_LT((w.tail(t) - expect).norm(), 1e-14 * expect.norm());
}

INSTANTIATE_TEST_SUITE_P(TailCholesky, TailOrder, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "Given" : "Camd"; });

TEST(TailCholesky, IndefiniteMatrixSolvesAndASingularOneIsNamed) {
  // Shifted by −4.5 the Laplacian's eigenvalues span (−4.5, 3.5): indefinite, nonsingular.
  const SpMat k = laplacian(-4.5);
  core::TailCholesky f;
  ASSERT_EQ(f.factorize(k, edge()), SolveStatus::kConverged) << f.report().message;
  EXPECT_LT(f.tail_pivots().minCoeff(), 0.0);
  const int n = static_cast<int>(k.rows());
  VecX b(n), w, x;
  for (int i = 0; i < n; ++i) b[i] = std::cos(0.11 * i);
  ASSERT_EQ(f.forward(b, w), SolveStatus::kConverged);
  ASSERT_EQ(f.backward(w, x), SolveStatus::kConverged);
  EXPECT_LT((k * x - b).norm(), 1e-11 * b.norm());
  // A zero pivot: one unknown with a zero diagonal and no coupling.
  SpMat z = laplacian(0.01);
  z.coeffRef(5, 5) = 0.0;
  for (int j : {4, 6, 5 + kSide}) z.coeffRef(5, j) = z.coeffRef(j, 5) = 0.0;
  EXPECT_EQ(f.factorize(z, edge()), SolveStatus::kSingular);
}

// The analysis is kept for a new matrix of the same pattern (no symbolic analysis, the new
// matrix solved to 1e-12) and made anew for a pattern with as many non-zeros in other places
// (one coupling moved), which a check of size and count alone would take for the old one and
// factorise with the wrong analysis.
TEST(TailCholesky, KeepsTheAnalysisOnlyForTheSamePattern) {
  const int n = kSide * kSide;
  VecX b(n);
  for (int i = 0; i < n; ++i) b[i] = std::sin(0.07 * i) + 0.3;
  core::TailCholesky f;
  auto solves = [&](const SpMat& k) {
    VecX w, x;
    if (f.forward(b, w) != SolveStatus::kConverged || f.backward(w, x) != SolveStatus::kConverged)
      return false;
    return (k * x - b).norm() < 1e-12 * b.norm();
  };
  const SpMat k1 = laplacian(0.1), k2 = laplacian(0.7);
  ASSERT_EQ(f.factorize(k1, edge()), SolveStatus::kConverged);
  ASSERT_EQ(f.factorize(k2, edge()), SolveStatus::kConverged);
  EXPECT_EQ(f.report().symbolic_analyses, 1);
  EXPECT_TRUE(solves(k2));
  SpMat k3 = laplacian(0.7);
  k3.coeffRef(0, 1) = k3.coeffRef(1, 0) = 0.0;
  k3.prune(0.0);
  k3.coeffRef(0, 2) = k3.coeffRef(2, 0) = -1.0;
  k3.makeCompressed();
  ASSERT_EQ(k3.nonZeros(), k2.nonZeros());
  ASSERT_EQ(f.factorize(k3, edge()), SolveStatus::kConverged);
  EXPECT_EQ(f.report().symbolic_analyses, 2);
  EXPECT_TRUE(solves(k3));
}

// TailAnalyses: a second factor of the same pattern and tail takes the first one's analysis
// (no analysis of its own) and solves to the same precision; one with another tail, or another
// pattern, analyses anew; the oldest of more analyses than it keeps is dropped.
TEST_P(TailOrder, SharedAnalysesServeOnlyTheSamePatternAndTail) {
  const int n = kSide * kSide;
  VecX b(n);
  for (int i = 0; i < n; ++i) b[i] = std::cos(0.05 * i) - 0.2;
  auto analyses = std::make_shared<core::TailAnalyses>();
  // A new factor per call, as a Newton iteration makes a new condensation; its analyses.
  auto analyses_of = [&](const SpMat& k, const std::vector<int>& tail, double& residual) {
    core::TailCholesky f;
    order(f);
    f.set_analyses(analyses);
    VecX w, x;
    if (f.factorize(k, tail) != SolveStatus::kConverged || f.forward(b, w) != SolveStatus::kConverged ||
        f.backward(w, x) != SolveStatus::kConverged)
      return -1;
    residual = (k * x - b).norm() / b.norm();
    return f.report().symbolic_analyses;
  };
  std::vector<int> left;
  for (int i = 0; i < kSide; ++i) left.push_back(i * kSide);  // the left column
  const SpMat k1 = laplacian(0.1), k2 = laplacian(0.9);
  SpMat k3 = laplacian(0.9);
  k3.coeffRef(0, 2) = k3.coeffRef(2, 0) = -0.5;  // one entry more
  k3.makeCompressed();
  double r = 1.0;
  EXPECT_EQ(analyses_of(k1, edge(), r), 1);
  EXPECT_EQ(analyses_of(k2, edge(), r), 0);  // same pattern, new values
  EXPECT_LT(r, 1e-12);
  EXPECT_EQ(analyses_of(k2, left, r), 1);    // another tail
  EXPECT_LT(r, 1e-12);
  EXPECT_EQ(analyses_of(k1, edge(), r), 0);  // the first still kept
  EXPECT_EQ(analyses_of(k3, edge(), r), 1);  // another pattern
  EXPECT_LT(r, 1e-12);
  std::vector<int> corner = {0, 1, kSide, kSide + 1};
  EXPECT_EQ(analyses_of(k1, corner, r), 1);  // a fourth: the oldest kept (edge, k1) goes
  EXPECT_EQ(analyses_of(k1, left, r), 0);
  EXPECT_EQ(analyses_of(k1, edge(), r), 1);
  EXPECT_LT(r, 1e-12);
}
