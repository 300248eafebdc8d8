// Finite-strain kernels: the tangent is the exact derivative of the internal force, a rigid
// rotation produces no stress, and the small-displacement limit is the linear stiffness.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/elasticity_kernels.hpp"
#include "core/finite_strain_kernels.hpp"

using namespace c2d;
using namespace c2d::core;

namespace {

Material steel(PlaneState state) {
  Material m;
  m.young = 210000.0;
  m.poisson = 0.3;
  m.thickness = 2.0;
  m.state = state;
  return m;
}

Eigen::MatrixX2d element_coords(int nn) {
  Eigen::MatrixX2d x(nn, 2);
  x.topRows(3) << 0.1, 0.0, 1.2, 0.2, 0.3, 0.9;
  if (nn == 6) {
    x.row(3) = 0.5 * (x.row(0) + x.row(1)) + Eigen::RowVector2d(0.02, -0.03);
    x.row(4) = 0.5 * (x.row(1) + x.row(2));
    x.row(5) = 0.5 * (x.row(2) + x.row(0)) + Eigen::RowVector2d(-0.02, 0.01);
  }
  return x;
}

class FiniteStrain : public ::testing::TestWithParam<std::tuple<int, PlaneState>> {};

}  // namespace

TEST_P(FiniteStrain, TangentMatchesFiniteDifferencesOfTheInternalForce) {
  const auto [nn, state] = GetParam();
  const Material mat = steel(state);
  const Eigen::MatrixX2d x = element_coords(nn);
  std::mt19937 rng(11 + nn);
  std::uniform_real_distribution<double> dist(-0.15, 0.15);
  for (int trial = 0; trial < 5; ++trial) {
    // A random deformed state: a rotation of up to 60° plus strains of several per cent.
    const double th = 0.2 * trial;
    Eigen::Matrix2d r;
    r << std::cos(th), -std::sin(th), std::sin(th), std::cos(th);
    LocalVector u(2 * nn);
    for (int a = 0; a < nn; ++a) {
      const Vec2 xa = x.row(a).transpose();
      u.segment<2>(2 * a) = r * xa - xa + Vec2(dist(rng), dist(rng)) * 0.3;
    }
    LocalVector f;
    LocalMatrix k;
    ASSERT_TRUE(finite_strain_element(x, u, mat, &f, &k));
    // Central differences: error O(h²) + round-off O(eps |f| / h); h = 1e-6 balances them.
    LocalMatrix kfd(2 * nn, 2 * nn);
    const double h = 1e-6;
    for (int j = 0; j < 2 * nn; ++j) {
      LocalVector up = u, um = u, fp, fm;
      up[j] += h;
      um[j] -= h;
      finite_strain_element(x, up, mat, &fp, nullptr);
      finite_strain_element(x, um, mat, &fm, nullptr);
      kfd.col(j) = (fp - fm) / (2 * h);
    }
    EXPECT_LT((k - kfd).norm() / k.norm(), 1e-6) << "trial " << trial;
    EXPECT_LT((k - k.transpose()).norm() / k.norm(), 1e-12);  // hyperelastic: symmetric
  }
}

TEST_P(FiniteStrain, RigidRotationIsStressFree) {
  const auto [nn, state] = GetParam();
  const Material mat = steel(state);
  const Eigen::MatrixX2d x = element_coords(nn);
  for (double deg : {9.0, 45.0, 90.0, 170.0}) {
    const double th = deg * M_PI / 180.0;
    Eigen::Matrix2d r;
    r << std::cos(th), -std::sin(th), std::sin(th), std::cos(th);
    LocalVector u(2 * nn);
    for (int a = 0; a < nn; ++a) {
      const Vec2 xa = x.row(a).transpose();
      u.segment<2>(2 * a) = r * xa - xa;
    }
    LocalVector f;
    ASSERT_TRUE(finite_strain_element(x, u, mat, &f, nullptr));
    EXPECT_LT(f.cwiseAbs().maxCoeff(), 1e-9 * mat.young);
    EXPECT_LT(finite_strain_point_stresses(x, mat, u).cwiseAbs().maxCoeff(), 1e-9 * mat.young);
  }
}

TEST_P(FiniteStrain, SmallDisplacementLimitIsTheLinearStiffness) {
  const auto [nn, state] = GetParam();
  const Material mat = steel(state);
  // Straight sides: the linear kernel's 3-point rule is then exact too.
  Eigen::MatrixX2d x = element_coords(nn);
  if (nn == 6)
    for (int m = 0; m < 3; ++m) x.row(3 + m) = 0.5 * (x.row(m) + x.row((m + 1) % 3));
  LocalMatrix k;
  ASSERT_TRUE(finite_strain_element(x, LocalVector::Zero(2 * nn), mat, nullptr, &k));
  const LocalMatrix kl = element_stiffness(x, mat);
  EXPECT_LT((k - kl).norm() / kl.norm(), 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Elements, FiniteStrain,
                         ::testing::Combine(::testing::Values(3, 6),
                                            ::testing::Values(PlaneState::kPlaneStress,
                                                              PlaneState::kPlaneStrain)));
