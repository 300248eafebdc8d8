#include "core/error_estimator.hpp"

#include <algorithm>
#include <cmath>

#include "core/triangle.hpp"

namespace c2d::core {

namespace {

template <int NN>
void integrate(const Mesh& mesh, const std::vector<Material>& materials,
               const ElementStresses& stresses, const Eigen::Matrix3Xd& smoothed,
               ErrorEstimate& est, double& energy2) {
  using Tri = Triangle<NN>;
  // Each element's energy on its own, summed in element order after: the sum does not depend
  // on the threads.
  std::vector<double> energy(mesh.num_elements(), 0.0);
#pragma omp parallel for schedule(static) if (mesh.num_elements() >= kMinParallelElements)
  for (int e = 0; e < mesh.num_elements(); ++e) {
    typename Tri::ShapeGrad g;
    const typename Tri::Coords x = mesh.element_coords(e);
    const Material& mat = materials[mesh.element_material[e]];
    const Mat3 c = mat.compliance();
    Eigen::Matrix<double, 3, NN> nodal;
    for (int i = 0; i < NN; ++i) nodal.col(i) = smoothed.col(mesh.elements[e][i]);
    double err2 = 0.0, en2 = 0.0;
    for (const auto& q : rule_degree4()) {
      const double w = Tri::shape_grad(x, q.a, q.b, g) * q.weight * mat.thickness;
      const Voigt star = nodal * Tri::shape(q.a, q.b);
      const Voigt diff = star - interpolate_element_stress(stresses.at_points[e], q.a, q.b);
      err2 += diff.dot(c * diff) * w;
      en2 += star.dot(c * star) * w;
    }
    est.element_error[e] = std::sqrt(std::max(err2, 0.0));
    energy[e] = en2;
  }
  for (double en2 : energy) energy2 += en2;
}

}  // namespace

ErrorEstimate estimate_error(const Mesh& mesh, const std::vector<Material>& materials,
                             const ElementStresses& stresses, const Eigen::Matrix3Xd& smoothed,
                             double target) {
  ErrorEstimate est;
  est.target = target;
  est.element_error.assign(mesh.num_elements(), 0.0);
  double energy2 = 0.0;
  if (mesh.order == 1)
    integrate<3>(mesh, materials, stresses, smoothed, est, energy2);
  else
    integrate<6>(mesh, materials, stresses, smoothed, est, energy2);
  double err2 = 0.0;
  for (double ee : est.element_error) err2 += ee * ee;
  est.error_norm = std::sqrt(err2);
  est.energy_norm = std::sqrt(energy2);
  // A stress-free state (a rigid motion, an unloaded body) has nothing to estimate: its
  // relative error would be round-off over round-off. Below 1e-10 E the field counts as zero.
  double young = 0.0;
  for (const auto& m : materials) young = std::max(young, m.young);
  const bool stress_free = smoothed.size() == 0 || smoothed.cwiseAbs().maxCoeff() <= 1e-10 * young;
  const double denom = stress_free ? 0.0 : target * est.energy_norm;
  est.global_parameter = denom > 0 ? est.error_norm / denom : 0.0;
  est.relative_error = denom > 0 ? est.error_norm / est.energy_norm : 0.0;
  const double sqrt_n = std::sqrt(static_cast<double>(mesh.num_elements()));
  est.local_parameter.resize(mesh.num_elements());
  for (int e = 0; e < mesh.num_elements(); ++e)
    est.local_parameter[e] = denom > 0 ? est.element_error[e] * sqrt_n / denom : 0.0;
  return est;
}

}  // namespace c2d::core
