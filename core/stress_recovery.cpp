#include "core/stress_recovery.hpp"

#include <stdexcept>

#include "core/elasticity_kernels.hpp"
#include "core/finite_strain_kernels.hpp"
#include "core/spd_solver.hpp"
#include "core/triangle.hpp"

namespace c2d::core {

ElementStresses compute_element_stresses(const Mesh& mesh, const std::vector<Material>& materials,
                                         const VecX& u, bool finite_strain) {
  ElementStresses s;
  const int nn = mesh.nodes_per_element();
  s.at_points.resize(mesh.num_elements());
  s.at_nodes.resize(mesh.num_elements());
  LocalVector ue(2 * nn);
  for (int e = 0; e < mesh.num_elements(); ++e) {
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

template <int NN>
Eigen::Matrix3Xd l2_projection(const Mesh& mesh, const std::vector<Material>& materials,
                               const ElementStresses& stresses) {
  using Tri = Triangle<NN>;
  std::vector<Triplet> mass;
  mass.reserve(static_cast<size_t>(mesh.num_elements()) * NN * NN);
  Eigen::MatrixX3d rhs = Eigen::MatrixX3d::Zero(mesh.num_nodes(), 3);
  typename Tri::ShapeGrad g;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const typename Tri::Coords x = mesh.element_coords(e);
    const double t = materials[mesh.element_material[e]].thickness;
    Eigen::Matrix<double, NN, NN> me = Eigen::Matrix<double, NN, NN>::Zero();
    Eigen::Matrix<double, NN, 3> re = Eigen::Matrix<double, NN, 3>::Zero();
    for (const auto& q : rule_degree4()) {
      const double w = Tri::shape_grad(x, q.a, q.b, g) * q.weight * t;
      const auto n = Tri::shape(q.a, q.b);
      me.noalias() += n * n.transpose() * w;
      re.noalias() +=
          n * interpolate_element_stress(stresses.at_points[e], q.a, q.b).transpose() * w;
    }
    for (int i = 0; i < NN; ++i) {
      rhs.row(mesh.elements[e][i]) += re.row(i);
      for (int j = 0; j < NN; ++j)
        mass.emplace_back(mesh.elements[e][i], mesh.elements[e][j], me(i, j));
    }
  }
  SpMat m(mesh.num_nodes(), mesh.num_nodes());
  m.setFromTriplets(mass.begin(), mass.end());
  SpdSolver solver;
  Eigen::Matrix3Xd out(3, mesh.num_nodes());
  if (solver.factorize(m) != SolveStatus::kConverged)
    throw std::logic_error("L2 stress projection: mass matrix not positive definite");
  for (int c = 0; c < 3; ++c) {
    VecX col;
    solver.solve(rhs.col(c), col);
    out.row(c) = col.transpose();
  }
  return out;
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
