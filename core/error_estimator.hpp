// Zienkiewicz-Zhu energy-norm error estimate, with the seed annex's global and local parameters.
#pragma once

#include <vector>

#include "core/material.hpp"
#include "core/mesh.hpp"
#include "core/stress_recovery.hpp"

namespace c2d::core {

struct ErrorEstimate {
  double error_norm = 0.0;         ///< ||e|| = sqrt(Σ_e t ∫ (σ* - σ_h)ᵀ D⁻¹ (σ* - σ_h) dA)
  double energy_norm = 0.0;        ///< ||U|| = sqrt(Σ_e t ∫ σ*ᵀ D⁻¹ σ* dA)   (seed annex 3)
  double target = 0.05;            ///< η, the admissible relative error
  double global_parameter = 0.0;   ///< ξ_g = ||e|| / (η ||U||)
  double relative_error = 0.0;     ///< ||e|| / ||U||
  std::vector<double> element_error;    ///< ||e||_e
  std::vector<double> local_parameter;  ///< ξ_e = ||e||_e sqrt(n) / (η ||U||)
};

/// σ* is the smoothed nodal field interpolated with the element's own shape functions.
ErrorEstimate estimate_error(const Mesh& mesh, const std::vector<Material>& materials,
                             const ElementStresses& stresses, const Eigen::Matrix3Xd& smoothed,
                             double target);

}  // namespace c2d::core
