// The scene's [[obstacle]], [[contact]] and [[constraint]] tables (docs/scene.md), parsed by the
// constraints module from the scene's TOML so that core/ knows nothing about constraints.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "constraints/constraint_strategy.hpp"
#include "constraints/contact_detection.hpp"
#include "constraints/equality.hpp"
#include "constraints/friction_law.hpp"
#include "core/scene.hpp"

namespace c2d::constraints {

/// A pair's friction (docs/scene.md): a law from the friction-law registry with its parameters;
/// none: frictionless.
struct FrictionSpec {
  std::string law;                          ///< the registry's name
  std::shared_ptr<const FrictionLaw> model;  ///< null: frictionless
  double penalty_ratio = 1.0;               ///< penalty-type methods: k_t / k
  bool enabled() const { return model != nullptr; }
};

struct ContactPairSpec {
  std::string name;
  core::SelectionSpec slave;
  std::optional<core::SelectionSpec> master;  ///< master surface (boundary edges of a body)
  int obstacle = -1;                          ///< or an obstacle index
  std::string detection = "node_to_segment";  ///< node_to_segment | node_to_node
  std::optional<Vec2> direction;              ///< node_to_node: fixed direction master -> slave
  double search_distance = -1.0;              ///< < 0: automatic
  FrictionSpec friction;
  std::string where;
};

/// A [[constraint]] (docs/scene.md): equality rows on displacements, enforced by the run's
/// constraint method like the contacts; its type's class (equality.hpp) makes the rows.
struct EqualitySpec {
  std::string name;
  std::string type;
  std::string where;
  std::shared_ptr<const EqualityConstraint> constraint;
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
