#include "core/elasticity_kernels.hpp"

#include <array>
#include <cassert>

#include "core/triangle.hpp"

namespace c2d::core {

namespace {

template <int NN>
typename Triangle<NN>::Coords fixed_coords(const Eigen::MatrixX2d& x) {
  assert(x.rows() == NN);
  return x;
}

template <int NN>
LocalMatrix stiffness(const Eigen::MatrixX2d& xd, const Material& mat) {
  using Tri = Triangle<NN>;
  const auto x = fixed_coords<NN>(xd);
  const Mat3 d = mat.elasticity();
  Eigen::Matrix<double, 2 * NN, 2 * NN> k = Eigen::Matrix<double, 2 * NN, 2 * NN>::Zero();
  typename Tri::ShapeGrad g;
  for (const auto& q : Tri::stiffness_rule()) {
    const double det = Tri::shape_grad(x, q.a, q.b, g);
    const auto bm = Tri::strain_matrix(g);
    k.noalias() += bm.transpose() * d * bm * (det * q.weight * mat.thickness);
  }
  return k;
}

template <int NN>
Voigt stress_at(const Eigen::MatrixX2d& xd, const Material& mat, const LocalVector& ue, double a,
                double b) {
  using Tri = Triangle<NN>;
  const auto x = fixed_coords<NN>(xd);
  typename Tri::ShapeGrad g;
  Tri::shape_grad(x, a, b, g);
  return mat.elasticity() * (Tri::strain_matrix(g) * ue.head<2 * NN>());
}

template <int NN>
Eigen::Matrix3Xd point_stresses(const Eigen::MatrixX2d& x, const Material& mat,
                                const LocalVector& ue) {
  const auto pts = Triangle<NN>::stress_points();
  Eigen::Matrix3Xd s(3, pts.size());
  for (size_t k = 0; k < pts.size(); ++k) s.col(k) = stress_at<NN>(x, mat, ue, pts[k].a, pts[k].b);
  return s;
}

template <int NN>
LocalVector body_force(const Eigen::MatrixX2d& xd, double thickness, const Vec2& bf) {
  using Tri = Triangle<NN>;
  const auto x = fixed_coords<NN>(xd);
  LocalVector f = LocalVector::Zero(2 * NN);
  typename Tri::ShapeGrad g;
  for (const auto& q : rule_degree2()) {
    const double det = Tri::shape_grad(x, q.a, q.b, g);
    const auto n = Tri::shape(q.a, q.b);
    for (int i = 0; i < NN; ++i) f.segment<2>(2 * i) += n[i] * bf * det * q.weight * thickness;
  }
  return f;
}

template <int NN>
double area(const Eigen::MatrixX2d& xd) {
  using Tri = Triangle<NN>;
  const auto x = fixed_coords<NN>(xd);
  typename Tri::ShapeGrad g;
  double s = 0.0;
  for (const auto& q : rule_degree2()) s += Tri::shape_grad(x, q.a, q.b, g) * q.weight;
  return s;
}

// 3-point Gauss-Legendre on [-1, 1] (exact to degree 5).
constexpr std::array<double, 3> kGaussX{-0.774596669241483377, 0.0, 0.774596669241483377};
constexpr std::array<double, 3> kGaussW{5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};

// 1D shape functions on [-1, 1] for an edge with nodes (end0, end1[, mid]).
void edge_shape(int nn, double s, Eigen::Vector3d& n, Eigen::Vector3d& dn) {
  if (nn == 2) {
    n << 0.5 * (1 - s), 0.5 * (1 + s), 0.0;
    dn << -0.5, 0.5, 0.0;
  } else {
    n << 0.5 * s * (s - 1), 0.5 * s * (s + 1), 1 - s * s;
    dn << s - 0.5, s + 0.5, -2 * s;
  }
}

Vec2 edge_tangent(const Eigen::MatrixX2d& x, const Eigen::Vector3d& dn) {
  Vec2 t = Vec2::Zero();
  for (int i = 0; i < x.rows(); ++i) t += dn[i] * x.row(i).transpose();
  return t;
}

}  // namespace

LocalMatrix element_stiffness(const Eigen::MatrixX2d& x, const Material& mat) {
  return x.rows() == 3 ? stiffness<3>(x, mat) : stiffness<6>(x, mat);
}

Eigen::Matrix3Xd element_point_stresses(const Eigen::MatrixX2d& x, const Material& mat,
                                        const LocalVector& ue) {
  return x.rows() == 3 ? point_stresses<3>(x, mat, ue) : point_stresses<6>(x, mat, ue);
}

Voigt element_stress_at(const Eigen::MatrixX2d& x, const Material& mat, const LocalVector& ue,
                        double a, double b) {
  return x.rows() == 3 ? stress_at<3>(x, mat, ue, a, b) : stress_at<6>(x, mat, ue, a, b);
}

Eigen::Matrix3Xd extrapolate_to_nodes(const Eigen::Matrix3Xd& ps, int nodes) {
  Eigen::Matrix3Xd out(3, nodes);
  if (ps.cols() == 1) {
    out.colwise() = ps.col(0);
    return out;
  }
  // Reference coordinates of the T6 nodes; the linear field through the 3 points at
  // (p, p), (4p, p), (p, 4p), p = 1/6, evaluated there.
  static const double ref[6][2] = {{0, 0}, {1, 0}, {0, 1}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}};
  const double p = 1.0 / 6.0;
  for (int i = 0; i < nodes; ++i) {
    const double s = (ref[i][0] - p) / (3 * p), t = (ref[i][1] - p) / (3 * p);
    out.col(i) = (1 - s - t) * ps.col(0) + s * ps.col(1) + t * ps.col(2);
  }
  return out;
}

LocalVector element_body_force(const Eigen::MatrixX2d& x, double thickness, const Vec2& b) {
  return x.rows() == 3 ? body_force<3>(x, thickness, b) : body_force<6>(x, thickness, b);
}

double element_area(const Eigen::MatrixX2d& x) {
  return x.rows() == 3 ? area<3>(x) : area<6>(x);
}

Eigen::VectorXd edge_load(const Eigen::MatrixX2d& x, double thickness, const Vec2& traction,
                          double pressure) {
  const int nn = static_cast<int>(x.rows());
  Eigen::VectorXd f = Eigen::VectorXd::Zero(2 * nn);
  Eigen::Vector3d n, dn;
  for (int q = 0; q < 3; ++q) {
    edge_shape(nn, kGaussX[q], n, dn);
    const Vec2 tangent = edge_tangent(x, dn);  // dx/dξ, |.| = ds/dξ
    const Vec2 outward_scaled(tangent.y(), -tangent.x());           // n * ds/dξ
    const Vec2 tau_ds = traction * tangent.norm() - pressure * outward_scaled;
    for (int i = 0; i < nn; ++i) f.segment<2>(2 * i) += n[i] * tau_ds * kGaussW[q] * thickness;
  }
  return f;
}

Eigen::MatrixXd edge_pressure_matrix(int nodes, double thickness, double pressure) {
  // f_i = −p t Σ_q w_q N_i (t_y, −t_x), t = Σ_j N_j' x_j: ∂f_i/∂x_j = −p t Σ_q w_q N_i N_j' J,
  // J = [[0, 1], [−1, 0]].
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(2 * nodes, 2 * nodes);
  Eigen::Vector3d n, dn;
  for (int q = 0; q < 3; ++q) {
    edge_shape(nodes, kGaussX[q], n, dn);
    for (int i = 0; i < nodes; ++i)
      for (int j = 0; j < nodes; ++j) {
        const double c = -pressure * thickness * kGaussW[q] * n[i] * dn[j];
        m(2 * i, 2 * j + 1) += c;
        m(2 * i + 1, 2 * j) -= c;
      }
  }
  return m;
}

double edge_length(const Eigen::MatrixX2d& x) {
  const int nn = static_cast<int>(x.rows());
  double l = 0.0;
  Eigen::Vector3d n, dn;
  for (int q = 0; q < 3; ++q) {
    edge_shape(nn, kGaussX[q], n, dn);
    l += edge_tangent(x, dn).norm() * kGaussW[q];
  }
  return l;
}

}  // namespace c2d::core
