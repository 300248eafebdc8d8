// The model's springs (docs/scene.md, [[spring]]): their internal forces and stiffness.
// Small strain: linear about the reference configuration (a node-to-node spring acts along the
// line between its nodes as they were). Finite strain: a spring to ground keeps its axes, a
// node-to-node spring turns with its nodes (co-rotational): N = k (ℓ − L), f_b = −f_a = N e,
// K_bb = k e eᵀ + (N/ℓ)(I − e eᵀ), with e the current unit direction from a to b.
#pragma once

#include "core/model.hpp"
#include "core/types.hpp"

namespace c2d::core {

/// Adds the springs' internal forces at displacement u (full vector) to f (full vector).
void add_spring_forces(const Model& model, const VecX& u, bool finite_strain, VecX& f);

/// The springs' stiffness at u on the free DOFs (n_free × n_free); with `du_constrained` (full
/// vector, zero on free DOFs), also adds their K_fc du_c to `lift` (n_free).
SpMat spring_stiffness(const Model& model, const VecX& u, bool finite_strain,
                       const VecX* du_constrained = nullptr, VecX* lift = nullptr);

/// The axial force of spring s at u (tension positive; to ground: |k ∘ u_a|, the force's size).
double spring_force(const Model& model, const Spring& s, const VecX& u, bool finite_strain);

}  // namespace c2d::core
