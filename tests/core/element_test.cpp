// Element stiffness properties: symmetry, positive semi-definiteness, exactly three zero-energy
// modes (two translations, one rotation), for T3 and T6 on distorted and curved elements.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "core/elasticity_kernels.hpp"
#include "core/material.hpp"

using namespace c2d;
using namespace c2d::core;

namespace {

Material steel(PlaneState s) {
  Material m;
  m.young = 210000;
  m.poisson = 0.3;
  m.thickness = 2.0;
  m.state = s;
  return m;
}

void check_stiffness(const Eigen::MatrixX2d& x, const Material& mat) {
  const LocalMatrix k = element_stiffness(x, mat);
  const double scale = k.cwiseAbs().maxCoeff();
  // Symmetric to round-off.
  EXPECT_LT((k - k.transpose()).cwiseAbs().maxCoeff(), 1e-12 * scale);
  const Eigen::MatrixXd kd = k;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(kd);
  const Eigen::VectorXd lambda = eig.eigenvalues();
  int zeros = 0;
  for (int i = 0; i < lambda.size(); ++i) {
    EXPECT_GT(lambda[i], -1e-10 * lambda.maxCoeff()) << "negative eigenvalue " << lambda[i];
    if (std::abs(lambda[i]) < 1e-9 * lambda.maxCoeff()) ++zeros;
  }
  EXPECT_EQ(zeros, 3) << "expected exactly 3 rigid-body modes";
  // The rigid modes are in the null space: translations and an infinitesimal rotation.
  const int nn = static_cast<int>(x.rows());
  Eigen::VectorXd tx(2 * nn), ty(2 * nn), rot(2 * nn);
  for (int i = 0; i < nn; ++i) {
    tx.segment<2>(2 * i) << 1, 0;
    ty.segment<2>(2 * i) << 0, 1;
    rot.segment<2>(2 * i) << -x(i, 1), x(i, 0);
  }
  for (const auto& mode : {tx, ty, rot})
    EXPECT_LT((k * mode).norm(), 1e-10 * scale * mode.norm());
}

}  // namespace

TEST(ElementStiffness, T3DistortedHasThreeRigidModes) {
  Eigen::MatrixX2d x(3, 2);
  x << 0.1, -0.2, 2.3, 0.4, 0.7, 1.9;
  for (auto s : {PlaneState::kPlaneStress, PlaneState::kPlaneStrain}) check_stiffness(x, steel(s));
}

TEST(ElementStiffness, T6DistortedAndCurvedHasThreeRigidModes) {
  Eigen::MatrixX2d x(6, 2);
  // Corners of a skewed triangle; mid-side nodes moved off the chords (a curved element).
  x << 0.0, 0.0, 3.0, 0.5, 1.0, 2.5,  //
      1.5, 0.05, 2.1, 1.6, 0.45, 1.2;
  for (auto s : {PlaneState::kPlaneStress, PlaneState::kPlaneStrain}) check_stiffness(x, steel(s));
}

TEST(ElementStiffness, T3MatchesClosedForm) {
  // Unit right triangle, nu = 0: K_11 = t E/(2A) * (b1^2 + c1^2/2) * A ... checked against the
  // CST formula K = t A Bᵀ D B with b = (y2-y3, y3-y1, y1-y2)/(2A), c = (x3-x2, x1-x3, x2-x1)/(2A).
  Eigen::MatrixX2d x(3, 2);
  x << 0, 0, 1, 0, 0, 1;
  Material m;
  m.young = 1.0;
  m.poisson = 0.0;
  m.thickness = 1.0;
  const LocalMatrix k = element_stiffness(x, m);
  // b1 = -1, c1 = -1 (A = 1/2): K_u1u1 = t A (D11 b1^2 + D33 c1^2) = 0.5 * (1 + 0.5) = 0.75.
  EXPECT_NEAR(k(0, 0), 0.75, 1e-15);
  EXPECT_NEAR(k(0, 1), 0.5 * 0.5, 1e-15);  // t A (D12 + D33) b1 c1 = 0.5 * 0.5
}
