#include "core/size_field.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace c2d::core {

double SizeField::min() const {
  double h = std::numeric_limits<double>::infinity();
  for (const auto& s : sizes) h = std::min({h, s[0], s[1], s[2]});
  return h;
}

double SizeField::max() const {
  double h = 0.0;
  for (const auto& s : sizes) h = std::max({h, s[0], s[1], s[2]});
  return h;
}

double element_size(const Mesh& mesh, int e) {
  const auto& n = mesh.elements[e];
  return ((mesh.nodes[n[1]] - mesh.nodes[n[0]]).norm() + (mesh.nodes[n[2]] - mesh.nodes[n[1]]).norm() +
          (mesh.nodes[n[0]] - mesh.nodes[n[2]]).norm()) /
         3.0;
}

std::vector<SizeField> optimal_size_fields(const Mesh& mesh, const std::vector<double>& local_parameter,
                                           int num_bodies, const SizeLimits& limits) {
  if (static_cast<int>(local_parameter.size()) != mesh.num_elements())
    throw std::invalid_argument("optimal_size_fields: one local parameter per element expected");
  const double p = mesh.order;
  std::vector<double> nodal(mesh.num_nodes(), std::numeric_limits<double>::infinity());
  std::vector<double> h_new(mesh.num_elements());
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const double h = element_size(mesh, e);
    const double xi = local_parameter[e];
    // ξ_e = 0 (a stress-free element) asks for the largest growth allowed.
    const double ratio = xi > 0 ? std::pow(xi, -1.0 / p) : limits.max_growth;
    h_new[e] = h * std::clamp(ratio, limits.max_shrink, limits.max_growth);
    for (int i = 0; i < 3; ++i) nodal[mesh.elements[e][i]] = std::min(nodal[mesh.elements[e][i]], h_new[e]);
  }
  std::vector<SizeField> fields(num_bodies);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const int b = mesh.element_body[e];
    if (b < 0 || b >= num_bodies) continue;
    const auto& n = mesh.elements[e];
    fields[b].triangles.push_back({mesh.nodes[n[0]], mesh.nodes[n[1]], mesh.nodes[n[2]]});
    fields[b].sizes.push_back({nodal[n[0]], nodal[n[1]], nodal[n[2]]});
  }
  return fields;
}

}  // namespace c2d::core
