// The scene's [[obstacle]], [[contact]] and [[constraint]] tables (docs/scene.md), parsed by the
// constraints module from the scene's TOML so that core/ knows nothing about constraints.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "constraints/constraint_strategy.hpp"
#include "constraints/contact_detection.hpp"
#include "core/scene.hpp"

namespace c2d::constraints {

struct ContactPairSpec {
  std::string name;
  core::SelectionSpec slave;
  std::optional<core::SelectionSpec> master;  ///< master surface (boundary edges of a body)
  int obstacle = -1;                          ///< or an obstacle index
  std::string detection = "node_to_segment";  ///< node_to_segment | node_to_node
  std::optional<Vec2> direction;              ///< node_to_node: fixed direction master -> slave
  double search_distance = -1.0;              ///< < 0: automatic
  std::string where;
};

/// One term a_i u_{n_i, d_i} of a linear multipoint constraint: `on` selects one node.
struct EqualityTermSpec {
  core::SelectionSpec on;
  int dof = 0;  ///< 0: ux, 1: uy
  double coefficient = 1.0;
};

/// A [[constraint]] (docs/scene.md): equality rows on displacements, enforced by the run's
/// constraint method like the contacts.
struct EqualitySpec {
  enum class Type { kLinear, kEqual, kTie };
  Type type = Type::kLinear;
  std::string name;
  std::string where;
  std::vector<EqualityTermSpec> terms;  ///< linear: Σ a_i u_{n_i, d_i} = value
  double value = 0.0;
  core::SelectionSpec on;               ///< equal: every node of `on` shares u_dof
  int dof = 0;
  core::SelectionSpec slave, master;    ///< tie: slave nodes move with the master edges
};

struct ContactSceneSpec {
  std::vector<Obstacle> obstacles;
  std::vector<ContactPairSpec> pairs;
  std::vector<EqualitySpec> equalities;
  StrategyOptions options;
  bool empty() const { return pairs.empty() && equalities.empty(); }
};

/// Parses the contact tables of a TOML scene (and the seed's gap elements of a legacy file,
/// whose default method is the seed's own: penalty with the file's stiffness). `method`, when
/// not empty, overrides the scene's method (--method). Throws InputError.
ContactSceneSpec parse_contact_scene(const core::Scene& scene, const std::string& method = "");

}  // namespace c2d::constraints
