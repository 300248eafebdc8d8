// The scene's [[obstacle]] and [[contact]] tables (docs/scene.md), parsed by the constraints
// module from the scene's TOML so that core/ knows nothing about contact.
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

struct ContactSceneSpec {
  std::vector<Obstacle> obstacles;
  std::vector<ContactPairSpec> pairs;
  StrategyOptions options;
  bool empty() const { return pairs.empty(); }
};

/// Parses the contact tables of a TOML scene (and the seed's gap elements of a legacy file,
/// whose default method is the seed's own: penalty with the file's stiffness). `method`, when
/// not empty, overrides the scene's method (--method). Throws InputError.
ContactSceneSpec parse_contact_scene(const core::Scene& scene, const std::string& method = "");

}  // namespace c2d::constraints
