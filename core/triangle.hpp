// Shape functions and quadrature of the linear (T3) and quadratic (T6) triangles.
//
// Reference triangle (a, b) with a, b >= 0, a + b <= 1; L1 = 1 - a - b.
// T3: N = [L1, a, b].
// T6: corners 0..2 as T3, mid-side nodes 3 (0-1), 4 (1-2), 5 (2-0) - the seed's and gmsh's order.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <span>

namespace c2d::core {

struct QuadraturePoint {
  double a, b, weight;  ///< weights sum to 1/2, the reference area
};

/// 1-point centroid rule (degree 1).
std::span<const QuadraturePoint> rule_degree1();
/// 3-point rule at (1/6, 1/6), (2/3, 1/6), (1/6, 2/3) (degree 2): the seed's Gauss points.
std::span<const QuadraturePoint> rule_degree2();
/// 6-point Dunavant rule (degree 4).
std::span<const QuadraturePoint> rule_degree4();

template <int NN>
struct Triangle {
  static_assert(NN == 3 || NN == 6);
  static constexpr int kNodes = NN;
  static constexpr int kDofs = 2 * NN;
  using Shape = Eigen::Matrix<double, NN, 1>;
  using ShapeGrad = Eigen::Matrix<double, NN, 2>;  ///< row i: dN_i/d(a, b) or dN_i/d(x, y)
  using Coords = Eigen::Matrix<double, NN, 2>;     ///< row i: (x_i, y_i)

  static Shape shape(double a, double b) {
    Shape n;
    const double l1 = 1.0 - a - b;
    if constexpr (NN == 3) {
      n << l1, a, b;
    } else {
      n << l1 * (2 * l1 - 1), a * (2 * a - 1), b * (2 * b - 1), 4 * l1 * a, 4 * a * b, 4 * b * l1;
    }
    return n;
  }

  static ShapeGrad shape_grad_ref(double a, double b) {
    ShapeGrad g;
    if constexpr (NN == 3) {
      g << -1, -1, 1, 0, 0, 1;
    } else {
      const double l1 = 1.0 - a - b;
      g << -(4 * l1 - 1), -(4 * l1 - 1),  //
          4 * a - 1, 0.0,                 //
          0.0, 4 * b - 1,                 //
          4 * (l1 - a), -4 * a,           //
          4 * b, 4 * a,                   //
          -4 * b, 4 * (l1 - b);
    }
    return g;
  }

  /// Physical gradients dN/dx at (a, b); returns det J (> 0 for a counter-clockwise element).
  static double shape_grad(const Coords& x, double a, double b, ShapeGrad& grad) {
    const ShapeGrad gr = shape_grad_ref(a, b);
    const Eigen::Matrix2d jac = gr.transpose() * x;  // [dx/da dy/da; dx/db dy/db]
    const double det = jac.determinant();
    grad = gr * jac.inverse().transpose();
    return det;
  }

  /// Strain-displacement matrix B (3 x 2NN), Voigt [xx, yy, xy], DOFs ordered (u0, v0, u1, ...).
  static Eigen::Matrix<double, 3, 2 * NN> strain_matrix(const ShapeGrad& g) {
    Eigen::Matrix<double, 3, 2 * NN> bm = Eigen::Matrix<double, 3, 2 * NN>::Zero();
    for (int i = 0; i < NN; ++i) {
      bm(0, 2 * i) = g(i, 0);
      bm(1, 2 * i + 1) = g(i, 1);
      bm(2, 2 * i) = g(i, 1);
      bm(2, 2 * i + 1) = g(i, 0);
    }
    return bm;
  }

  /// Rule that integrates B^T D B exactly on a straight-sided element.
  static std::span<const QuadraturePoint> stiffness_rule() {
    return NN == 3 ? rule_degree1() : rule_degree2();
  }
  /// Points where stresses are sampled and reported (T3: centroid; T6: the seed's 3 points).
  static std::span<const QuadraturePoint> stress_points() { return stiffness_rule(); }
};

using T3 = Triangle<3>;
using T6 = Triangle<6>;

}  // namespace c2d::core
