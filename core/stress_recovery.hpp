// Stresses from a displacement field and their nodal smoothing.
#pragma once

#include <vector>

#include "core/material.hpp"
#include "core/mesh.hpp"
#include "core/types.hpp"

namespace c2d::core {

enum class Smoothing {
  kDirectAverage,  ///< plain mean of the element values at a node (the seed's default)
  kAreaAverage,    ///< mean weighted by element area
  kGlobalL2,       ///< global L2 projection M s = ∫ Nᵀ σ_h dA (sparse, consistent mass)
};

struct ElementStresses {
  std::vector<Eigen::Matrix3Xd> at_points;  ///< per element: stress points (T3: 1, T6: 3)
  std::vector<Eigen::Matrix3Xd> at_nodes;   ///< per element: extrapolated to its nodes
};

/// Element stresses of displacement u (full vector, 2 per node): small-strain stresses, or with
/// `finite_strain` the Cauchy stresses of the St. Venant–Kirchhoff kernels.
ElementStresses compute_element_stresses(const Mesh& mesh, const std::vector<Material>& materials,
                                         const VecX& u, bool finite_strain = false);

/// Stress inside an element from its stress-point values: constant (T3) or the linear field
/// through the 3 Gauss points (T6), at reference coordinates (a, b).
Voigt interpolate_element_stress(const Eigen::Matrix3Xd& at_points, double a, double b);

/// Continuous nodal stresses (3 x num_nodes) from element stresses.
Eigen::Matrix3Xd smooth_stresses(const Mesh& mesh, const std::vector<Material>& materials,
                                 const ElementStresses& stresses, Smoothing method);

}  // namespace c2d::core
