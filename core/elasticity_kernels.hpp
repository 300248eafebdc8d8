// Element kernels of small-strain linear elasticity on T3/T6 triangles.
//
// Weak form: find u with  t ∫_Ω ε(v)ᵀ D ε(u) dA = t ∫_Ω vᵀ b dA + t ∫_Γ vᵀ τ ds  for all v,
// t the thickness, Voigt order [xx, yy, xy] with engineering shear strain.
// Kernels see local arrays only (coordinates as an NN x 2 matrix, DOFs ordered u0, v0, u1, ...);
// the assembler owns the global numbering.
#pragma once

#include "core/material.hpp"
#include "core/types.hpp"

namespace c2d::core {

/// Element stiffness K_e = t ∫ Bᵀ D B dA (exact for straight-sided elements).
LocalMatrix element_stiffness(const Eigen::MatrixX2d& x, const Material& mat);

/// Stresses D B u_e at the element's stress points (T3: 1 centroid; T6: 3 seed Gauss points);
/// column k is point k.
Eigen::Matrix3Xd element_point_stresses(const Eigen::MatrixX2d& x, const Material& mat,
                                        const LocalVector& ue);

/// Stress at reference point (a, b) of the element (linear in T6, constant in T3).
Voigt element_stress_at(const Eigen::MatrixX2d& x, const Material& mat, const LocalVector& ue,
                        double a, double b);

/// Extrapolates stress-point values to the element's nodes (T3: constant; T6: the linear field
/// through the 3 Gauss points, the seed annex's s = (a - p)/(3p), t = (b - p)/(3p)).
Eigen::Matrix3Xd extrapolate_to_nodes(const Eigen::Matrix3Xd& point_stresses, int nodes);

/// Consistent nodal forces of a body force b (force per volume): t ∫ Nᵀ b dA.
LocalVector element_body_force(const Eigen::MatrixX2d& x, double thickness, const Vec2& b);

/// Area ∫ dA of the (possibly curved) element.
double element_area(const Eigen::MatrixX2d& x);

/// Consistent nodal forces of an edge traction on a boundary edge with 2 or 3 nodes (ends, then
/// mid-side), traverse direction with the body on the left: t ∫ Nᵀ τ ds.
/// The traction is τ = traction + (-pressure) n, n the outward normal.
Eigen::VectorXd edge_load(const Eigen::MatrixX2d& x, double thickness, const Vec2& traction,
                          double pressure);

/// A pressure that follows the edge: its nodal forces are linear in the nodes' current
/// positions, f = M x (x stacked (x₁, y₁, x₂, ...)), since n ds = J dx with J the quarter turn;
/// M (2nn × 2nn) is that matrix, not symmetric. edge_load(x, t, 0, p) = M x.
Eigen::MatrixXd edge_pressure_matrix(int nodes, double thickness, double pressure);

/// Length of a boundary edge with 2 or 3 nodes.
double edge_length(const Eigen::MatrixX2d& x);

}  // namespace c2d::core
