#include "core/finite_strain_kernels.hpp"

#include "core/triangle.hpp"

namespace c2d::core {

namespace {

struct PointState {
  Eigen::Matrix2d f, sigma;
  double j = 0.0;
};

// F, J and Cauchy stress at a point with reference gradients g0.
template <int NN>
PointState point_state(const typename Triangle<NN>::ShapeGrad& g0,
                       const typename Triangle<NN>::Coords& x_cur, const Mat3& d) {
  PointState p;
  p.f = x_cur.transpose() * g0;  // F_iJ = Σ_a x_ai ∂N_a/∂X_J
  p.j = p.f.determinant();
  const Eigen::Matrix2d e = 0.5 * (p.f.transpose() * p.f - Eigen::Matrix2d::Identity());
  const Voigt s = d * Voigt(e(0, 0), e(1, 1), 2.0 * e(0, 1));
  Eigen::Matrix2d sm;
  sm << s[0], s[2], s[2], s[1];
  p.sigma = p.f * sm * p.f.transpose() / p.j;
  return p;
}

template <int NN>
bool element(const Eigen::MatrixX2d& xd, const LocalVector& ue, const Material& mat,
             LocalVector* force, LocalMatrix* tangent) {
  using Tri = Triangle<NN>;
  const typename Tri::Coords x0 = xd;
  typename Tri::Coords xc = x0;
  for (int a = 0; a < NN; ++a) xc.row(a) += ue.segment<2>(2 * a).transpose();
  const Mat3 d = mat.elasticity();
  Eigen::Matrix<double, 2 * NN, 1> f = Eigen::Matrix<double, 2 * NN, 1>::Zero();
  Eigen::Matrix<double, 2 * NN, 2 * NN> k = Eigen::Matrix<double, 2 * NN, 2 * NN>::Zero();
  // T3: F is constant, one point is exact. T6: the integrands are of degree 4.
  const auto rule = NN == 3 ? rule_degree1() : rule_degree4();
  typename Tri::ShapeGrad g0;
  for (const auto& q : rule) {
    const double det0 = Tri::shape_grad(x0, q.a, q.b, g0);
    const PointState p = point_state<NN>(g0, xc, d);
    if (!(p.j > 0.0)) return false;
    const double dv = p.j * det0 * q.weight * mat.thickness;
    const typename Tri::ShapeGrad g = g0 * p.f.inverse();  // ∇_x N
    const auto bx = Tri::strain_matrix(g);
    const Voigt sv(p.sigma(0, 0), p.sigma(1, 1), p.sigma(0, 1));
    f.noalias() += bx.transpose() * sv * dv;
    if (tangent) {
      const Eigen::Matrix2d& F = p.f;
      Mat3 t;  // σ_v = (1/J) T S_v for engineering-shear Voigt vectors
      t << F(0, 0) * F(0, 0), F(0, 1) * F(0, 1), 2 * F(0, 0) * F(0, 1),  //
          F(1, 0) * F(1, 0), F(1, 1) * F(1, 1), 2 * F(1, 0) * F(1, 1),   //
          F(0, 0) * F(1, 0), F(0, 1) * F(1, 1), F(0, 0) * F(1, 1) + F(0, 1) * F(1, 0);
      const Mat3 c = t * d * t.transpose() / p.j;
      k.noalias() += bx.transpose() * c * bx * dv;
      const Eigen::Matrix<double, NN, NN> gsg = g * p.sigma * g.transpose() * dv;
      for (int a = 0; a < NN; ++a)
        for (int b = 0; b < NN; ++b) {
          k(2 * a, 2 * b) += gsg(a, b);
          k(2 * a + 1, 2 * b + 1) += gsg(a, b);
        }
    }
  }
  if (force) *force = f;
  if (tangent) *tangent = k;
  return true;
}

template <int NN>
Eigen::Matrix3Xd stresses(const Eigen::MatrixX2d& xd, const Material& mat, const LocalVector& ue) {
  using Tri = Triangle<NN>;
  const typename Tri::Coords x0 = xd;
  typename Tri::Coords xc = x0;
  for (int a = 0; a < NN; ++a) xc.row(a) += ue.segment<2>(2 * a).transpose();
  const auto pts = Tri::stress_points();
  Eigen::Matrix3Xd out(3, pts.size());
  typename Tri::ShapeGrad g0;
  for (size_t k = 0; k < pts.size(); ++k) {
    Tri::shape_grad(x0, pts[k].a, pts[k].b, g0);
    const PointState p = point_state<NN>(g0, xc, mat.elasticity());
    out.col(static_cast<int>(k)) = Voigt(p.sigma(0, 0), p.sigma(1, 1), p.sigma(0, 1));
  }
  return out;
}

}  // namespace

bool finite_strain_element(const Eigen::MatrixX2d& x_ref, const LocalVector& ue,
                           const Material& mat, LocalVector* force, LocalMatrix* tangent) {
  return x_ref.rows() == 3 ? element<3>(x_ref, ue, mat, force, tangent)
                           : element<6>(x_ref, ue, mat, force, tangent);
}

Eigen::Matrix3Xd finite_strain_point_stresses(const Eigen::MatrixX2d& x_ref, const Material& mat,
                                              const LocalVector& ue) {
  return x_ref.rows() == 3 ? stresses<3>(x_ref, mat, ue) : stresses<6>(x_ref, mat, ue);
}

}  // namespace c2d::core
