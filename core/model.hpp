// The discrete model built from a scene: mesh, materials, Dirichlet conditions, load vector.
#pragma once

#include <string>
#include <vector>

#include "core/dof_map.hpp"
#include "core/material.hpp"
#include "core/mesh.hpp"
#include "core/scene.hpp"

namespace c2d::core {

/// Nodes whose prescribed displacement follows a rigid rotation (a `rotate` support).
struct PrescribedRotation {
  std::vector<int> nodes;
  Vec2 center = Vec2::Zero();
  double angle = 0.0;  ///< at load factor 1
};

/// A spring of the model: node a to ground (b < 0; stiffness k_ground along x and y) or node a
/// to node b (axial stiffness k along the line between them).
struct Spring {
  std::string name;
  int a = -1, b = -1;
  Vec2 k_ground = Vec2::Zero();
  double k = 0.0;
};

struct Model {
  Mesh mesh;
  std::vector<Material> materials;
  std::vector<std::string> body_names;
  DofMap dofs;
  VecX external_force;  ///< full vector, 2 per node
  std::vector<int> node_material;  ///< material of (one of) the elements at each node
  double model_size = 1.0;  ///< bounding-box diagonal
  double mesh_seconds = 0.0;
  std::vector<PrescribedRotation> rotations;
  std::vector<Spring> springs;
};

/// The full vector of prescribed displacements at load factor λ (zero on free DOFs): λ × the
/// supports' values, except on rotated supports, which follow the rotation through λθ exactly
/// (not λ times its chord), so a load-stepped analysis turns them along the arc.
VecX prescribed_displacement(const Model& model, double lambda);

/// Meshes the bodies (or takes the legacy mesh), applies supports and loads. Throws InputError
/// when a selection matches nothing or a support conflicts.
Model build_model(const Scene& scene);

/// Nodes matched by a selection (sorted, unique). Throws InputError if none match.
std::vector<int> select_nodes(const Model& model, const SelectionSpec& s);
/// Boundary edges (indices) whose nodes all lie in the selection.
std::vector<int> select_edges(const Model& model, const SelectionSpec& s);

}  // namespace c2d::core
