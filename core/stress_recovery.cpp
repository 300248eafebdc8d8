#include "core/stress_recovery.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "core/errors.hpp"
#include "core/elasticity_kernels.hpp"
#include "core/finite_strain_kernels.hpp"
#include "core/triangle.hpp"

namespace c2d::core {

ElementStresses compute_element_stresses(const Mesh& mesh, const std::vector<Material>& materials,
                                         const VecX& u, bool finite_strain) {
  ElementStresses s;
  const int nn = mesh.nodes_per_element();
  s.at_points.resize(mesh.num_elements());
  s.at_nodes.resize(mesh.num_elements());
#pragma omp parallel for schedule(static) if (mesh.num_elements() >= kMinParallelElements)
  for (int e = 0; e < mesh.num_elements(); ++e) {
    LocalVector ue(2 * nn);
    for (int i = 0; i < nn; ++i) ue.segment<2>(2 * i) = u.segment<2>(2 * mesh.elements[e][i]);
    const Eigen::MatrixX2d x = mesh.element_coords(e);
    const Material& mat = materials[mesh.element_material[e]];
    s.at_points[e] = finite_strain ? finite_strain_point_stresses(x, mat, ue)
                                   : element_point_stresses(x, mat, ue);
    s.at_nodes[e] = extrapolate_to_nodes(s.at_points[e], nn);
  }
  return s;
}

Voigt interpolate_element_stress(const Eigen::Matrix3Xd& ps, double a, double b) {
  if (ps.cols() == 1) return ps.col(0);
  const double p = 1.0 / 6.0;
  const double s = (a - p) / (3 * p), t = (b - p) / (3 * p);
  return (1 - s - t) * ps.col(0) + s * ps.col(1) + t * ps.col(2);
}

namespace {

/// The mass-weighted projection's system M S = R, element by element: M's element matrices
/// are kept and applied without assembly.
template <int NN>
struct ElementMass {
  std::vector<Eigen::Matrix<double, NN, NN>> mass;
  Eigen::Matrix3Xd rhs;  ///< per node: ∫ N σ_h dA
  VecX diagonal;         ///< per node: M's diagonal

  ElementMass(const Mesh& mesh, const std::vector<Material>& materials,
              const ElementStresses& stresses)
      : mass(mesh.num_elements()) {
    using Tri = Triangle<NN>;
    std::vector<Eigen::Matrix<double, NN, 3>> re(mesh.num_elements());
#pragma omp parallel for schedule(static) if (mesh.num_elements() >= kMinParallelElements)
    for (int e = 0; e < mesh.num_elements(); ++e) {
      typename Tri::ShapeGrad g;
      const typename Tri::Coords x = mesh.element_coords(e);
      const double t = materials[mesh.element_material[e]].thickness;
      mass[e].setZero();
      re[e].setZero();
      for (const auto& q : rule_degree4()) {
        const double w = Tri::shape_grad(x, q.a, q.b, g) * q.weight * t;
        const auto n = Tri::shape(q.a, q.b);
        mass[e].noalias() += n * n.transpose() * w;
        re[e].noalias() +=
            n * interpolate_element_stress(stresses.at_points[e], q.a, q.b).transpose() * w;
      }
    }
    rhs = Eigen::Matrix3Xd::Zero(3, mesh.num_nodes());
    diagonal = VecX::Zero(mesh.num_nodes());
    for (int e = 0; e < mesh.num_elements(); ++e)
      for (int i = 0; i < NN; ++i) {
        rhs.col(mesh.elements[e][i]) += re[e].row(i).transpose();
        diagonal[mesh.elements[e][i]] += mass[e](i, i);
      }
  }

  /// y = M x for the three stress components at once.
  void apply(const Mesh& mesh, const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& y) const {
    y.setZero(3, x.cols());
    Eigen::Matrix<double, 3, NN> xe;
    for (int e = 0; e < mesh.num_elements(); ++e) {
      const auto& nodes = mesh.elements[e];
      for (int i = 0; i < NN; ++i) xe.col(i) = x.col(nodes[i]);
      const Eigen::Matrix<double, 3, NN> ye = xe * mass[e];  // M_e symmetric
      for (int i = 0; i < NN; ++i) y.col(nodes[i]) += ye.col(i);
    }
  }
};

/// Global L2 projection M S = R by conjugate gradients preconditioned with M's diagonal, the
/// three components side by side. For straight-sided elements every element's diagonally
/// scaled mass matrix is the same matrix, so the iteration count is bounded independently of
/// the mesh (Wathen 1987): about 10 iterations for T3 and 25 for T6 to a relative residual of
/// 1e-12, where a factorisation of M cost more than the displacement solve's triangular solves.
template <int NN>
Eigen::Matrix3Xd l2_projection(const Mesh& mesh, const std::vector<Material>& materials,
                               const ElementStresses& stresses) {
  const ElementMass<NN> m(mesh, materials, stresses);
  const Eigen::Index n = mesh.num_nodes();
  const Eigen::RowVectorXd inv_diag = m.diagonal.cwiseInverse().transpose();
  Eigen::Matrix3Xd s = (m.rhs.array().rowwise() * inv_diag.array()).matrix();
  Eigen::Matrix3Xd r(3, n), z(3, n), p(3, n), q(3, n);
  m.apply(mesh, s, q);
  r = m.rhs - q;
  z = (r.array().rowwise() * inv_diag.array()).matrix();
  p = z;
  Eigen::Array3d rz = (r.array() * z.array()).rowwise().sum();
  const Eigen::Array3d b2 = m.rhs.array().square().rowwise().sum();
  constexpr double kTolerance = 1e-12;
  constexpr int kMaxIterations = 1000;
  for (int it = 0;; ++it) {
    const Eigen::Array3d r2 = r.array().square().rowwise().sum();
    if ((r2 <= kTolerance * kTolerance * b2).all()) break;
    if (it == kMaxIterations || !r2.allFinite())
      throw std::logic_error("L2 stress projection: conjugate gradients on the mass matrix did "
                             "not converge (residual " + number_text(std::sqrt(r2.maxCoeff())) + ")");
    m.apply(mesh, p, q);
    const Eigen::Array3d pq = (p.array() * q.array()).rowwise().sum();
    const Eigen::Array3d alpha = (pq > 0).select(rz / pq, 0.0);
    s.array() += p.array().colwise() * alpha;
    r.array() -= q.array().colwise() * alpha;
    z = (r.array().rowwise() * inv_diag.array()).matrix();
    const Eigen::Array3d rz_next = (r.array() * z.array()).rowwise().sum();
    const Eigen::Array3d beta = (rz > 0).select(rz_next / rz, 0.0);
    p = (z.array() + p.array().colwise() * beta).matrix();
    rz = rz_next;
  }
  return s;
}

}  // namespace

Eigen::Matrix3Xd smooth_stresses(const Mesh& mesh, const std::vector<Material>& materials,
                                 const ElementStresses& stresses, Smoothing method) {
  if (method == Smoothing::kGlobalL2)
    return mesh.order == 1 ? l2_projection<3>(mesh, materials, stresses)
                           : l2_projection<6>(mesh, materials, stresses);
  Eigen::Matrix3Xd sum = Eigen::Matrix3Xd::Zero(3, mesh.num_nodes());
  VecX weight = VecX::Zero(mesh.num_nodes());
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const double w =
        method == Smoothing::kAreaAverage ? element_area(mesh.element_coords(e)) : 1.0;
    for (int i = 0; i < mesh.nodes_per_element(); ++i) {
      sum.col(mesh.elements[e][i]) += w * stresses.at_nodes[e].col(i);
      weight[mesh.elements[e][i]] += w;
    }
  }
  for (int n = 0; n < mesh.num_nodes(); ++n)
    if (weight[n] > 0) sum.col(n) /= weight[n];
  return sum;
}

}  // namespace c2d::core
