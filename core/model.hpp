// The discrete model built from a scene: mesh, materials, Dirichlet conditions, load vector.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/dof_map.hpp"
#include "core/fill_ordering.hpp"
#include "core/material.hpp"
#include "core/mesh.hpp"
#include "core/scene.hpp"

namespace c2d::core {

/// A piecewise-linear amplitude a(λ) through its table's points (an `amplitude` table).
struct Amplitude {
  AmplitudeTable table;
  double at(double lambda) const;
  double peak() const;  ///< the largest |a|
};

/// Nodes whose prescribed displacement follows a rigid rotation (a `rotate` support).
struct PrescribedRotation {
  std::vector<int> nodes;
  Vec2 center = Vec2::Zero();
  double angle = 0.0;  ///< at load factor 1 (at a = 1 with an amplitude)
  int amplitude = -1;  ///< its Model::motion_amplitudes entry, −1: none (the angle grows as λ)
};

/// A spring of the model: node a to ground (b < 0; stiffness k_ground along x and y) or node a
/// to node b (axial stiffness k along the line between them).
struct Spring {
  std::string name;
  int a = -1, b = -1;
  Vec2 k_ground = Vec2::Zero();
  double k = 0.0;
};

/// A rigid plate of the model ([[plate]]): its three DOFs u_x, u_y, θ follow the nodes' DOFs in
/// the full vector (dof, dof + 1, dof + 2); its rows tie the attached nodes to its motion
/// (constraints/equalities/rigid_plate.hpp).
struct RigidPlate {
  std::string name;
  Vec2 reference = Vec2::Zero();
  int dof = -1;
  std::vector<int> nodes;     ///< attached nodes, sorted
  bool normal_only = false;
  Vec2 normal = Vec2::Zero(); ///< unit outward normal of the attached (straight) edge
  std::string where;          ///< its table in the scene, for messages
};

struct Model {
  Mesh mesh;
  std::vector<Material> materials;
  std::vector<std::string> body_names;
  /// Full DOF numbering: 2 per node (2 n + component), then 3 per rigid plate.
  DofMap dofs;
  VecX external_force;  ///< full vector: the loads that grow as λ (a = λ), at λ = 1
  /// Loads with their own amplitude ([[load]] amplitude, a [[plate]]'s force and moment):
  /// a(λ) × force.
  struct AmplitudeLoad {
    VecX force;  ///< full vector, at a = 1
    Amplitude amplitude;
    double at(double lambda) const { return amplitude.at(lambda); }
  };
  std::vector<AmplitudeLoad> amplitude_loads;
  /// Prescribed motions with their own amplitude ([[support]] and [[plate]] amplitude): a DOF
  /// of motion amplitude k takes a_k(λ) × its prescribed value, the others λ × theirs.
  std::vector<Amplitude> motion_amplitudes;
  std::vector<int> dof_amplitude;  ///< per full DOF: its motion amplitude, −1: none (λ)
  /// The dead external force at load factor λ: λ external_force + Σ a(λ) force (full vector).
  VecX external_force_at(double lambda) const;
  std::vector<int> node_material;  ///< material of (one of) the elements at each node
  double model_size = 1.0;  ///< bounding-box diagonal
  double mesh_seconds = 0.0;
  std::vector<PrescribedRotation> rotations;
  std::vector<Spring> springs;
  std::vector<RigidPlate> plates;
  /// Follower pressures ([[load]] follower = true): their nodal forces f = M x at the current
  /// positions x (full DOFs; empty when none). external_force holds their reference value M X.
  SpMat follower_matrix;
  VecX follower_reference;  ///< M X (full; empty when none)
  std::string follower_where;  ///< the first follower load's table, for messages
  /// The free DOFs' fill-reducing elimination order and split (mesh_fill_order of mesh and dofs),
  /// set once by build_model for every factorisation of the run: the plain solve, the finite-
  /// strain Newton, the contact methods. Null: CHOLMOD orders each matrix itself.
  std::shared_ptr<const FillOrder> fill_order;
};

/// The full vector of prescribed displacements at load factor λ (zero on free DOFs): λ × the
/// supports' values (a(λ) × with an amplitude), except on rotated supports, which follow the
/// rotation through λθ (a(λ)θ) exactly (not its chord), so a load-stepped analysis turns them
/// along the arc.
VecX prescribed_displacement(const Model& model, double lambda);

/// The same with every value a chord, λ or a(λ) × its value at 1 (a rotation's too): what a
/// small-strain analysis prescribes.
VecX prescribed_values(const Model& model, double lambda);

/// The prescribed values of the DOFs under motion amplitude `amplitude` at a = 1 (−1: those
/// that grow as λ, at λ = 1), zero elsewhere: prescribed_values is λ × the first plus
/// a_k(λ) × each other.
VecX prescribed_group(const Model& model, int amplitude);

/// Whether a load or a prescribed motion has its own amplitude: the analysis is staged.
bool has_amplitudes(const Model& model);

/// A support's or plate's amplitude as the model's next motion amplitude: its index in
/// Model::motion_amplitudes, −1 for none (an empty table).
int add_motion_amplitude(const AmplitudeTable& table, Model& model);

/// Meshes the bodies (or takes the legacy mesh), applies supports and loads. Throws InputError
/// when a selection matches nothing or a support conflicts.
Model build_model(const Scene& scene);

/// Nodes matched by a selection (sorted, unique). Throws InputError if none match.
std::vector<int> select_nodes(const Model& model, const SelectionSpec& s);
/// Boundary edges (indices) whose nodes all lie in the selection.
std::vector<int> select_edges(const Model& model, const SelectionSpec& s);

}  // namespace c2d::core
