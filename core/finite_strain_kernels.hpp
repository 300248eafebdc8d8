// Element kernels of large-displacement, small-strain elasticity (St. Venant–Kirchhoff) in the
// updated-Lagrangian form of the seed's annex.
//
// At the current configuration x = X + u: F = ∂x/∂X, Green–Lagrange strain E = ½(FᵀF − I),
// second Piola–Kirchhoff stress S = D E (D the plane stress/strain matrix of the material), Cauchy
// stress σ = F S Fᵀ / J. With B_x the strain matrix of the current gradients ∇_x N:
//   internal force      f = ∫_v B_xᵀ σ dv
//   material stiffness  K_D = ∫_v B_xᵀ c B_x dv,   c = (1/J) T D Tᵀ (D pushed forward by F)
//   geometric stiffness K_σ = ∫_v Gᵀ σ G dv,        (K_σ)_ab = (∇_x N_a · σ ∇_x N_b) I
// K_T = K_D + K_σ is the exact derivative of f (tested against finite differences). Voigt order
// [xx, yy, xy], engineering shear. Plane stress keeps the reference thickness (no thickness
// update: strains are small), so dv = J t dA_0.
#pragma once

#include "core/material.hpp"
#include "core/types.hpp"

namespace c2d::core {

/// Internal force and tangent K_T of an element at displacement ue (either may be null).
/// Returns false when the element is inverted (J ≤ 0 at a quadrature point).
bool finite_strain_element(const Eigen::MatrixX2d& x_ref, const LocalVector& ue,
                           const Material& mat, LocalVector* force, LocalMatrix* tangent);

/// Cauchy stresses at the element's stress points (the points of element_point_stresses).
Eigen::Matrix3Xd finite_strain_point_stresses(const Eigen::MatrixX2d& x_ref, const Material& mat,
                                              const LocalVector& ue);

}  // namespace c2d::core
