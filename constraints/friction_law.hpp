// How a pair's `friction` bounds the friction force of its rows (docs/scene.md, Friction): one
// class per law in constraints/friction_laws/, one line in the registry of friction_law.cpp.
// The scene parser asks the registry for the law named by `law` (or the one whose keys the
// table gives), which parses its own keys; the frictional set iteration, ipopt's Tresca
// problems and the outputs ask the law for its bound, never its name.
//
// In 2D a slipping row carries λ_t = ±bound(λ_n): with the slip's sign fixed, an affine bound
// keeps that condition linear in the multipliers, so each set iteration is one linear solve. A
// law is therefore given by affine pieces, λ_t ≤ offset + slope λ_n on the piece its normal
// force lies on; the set iteration tracks each row's piece like its stick/slip state.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace c2d::core {
class TomlView;
}

namespace c2d::constraints {

/// One affine piece of a row's bound: |λ_t| ≤ offset + slope λ_n (forces).
struct FrictionBound {
  double offset = 0.0;
  double slope = 0.0;
  int piece = 0;  ///< which piece of the law, so that the set iteration can track it
  double at(double normal_force) const { return offset + slope * normal_force; }
};

/// A parsed friction law.
class FrictionLaw {
 public:
  virtual ~FrictionLaw() = default;
  /// The piece of the bound at normal force `normal_force` (≥ 0) on a row whose share of the
  /// slave surface is `area` (a traction bound times the area is a force).
  virtual FrictionBound bound(double normal_force, double area) const = 0;
  /// Whether a row carries friction while open (its bound at zero normal force is positive).
  bool binds_open_rows(double area) const { return bound(0.0, area).at(0.0) > 0; }
};

struct FrictionLawInfo {
  std::string name;     ///< the value of `friction.law`
  std::string keys;     ///< its own keys, for the docs
  std::string summary;  ///< its bound, for the docs
  std::vector<std::string> key_names;  ///< its own keys; a table without `law` names the law
                                       ///< whose keys it gives, exactly
  /// Whether its bound is a traction over the row's share of the slave surface (node_to_node
  /// pairs have no slave surface and refuse it).
  bool traction = false;
  /// Its keys in an example (the registry test runs a block sliding on a floor under two normal
  /// pressures, 1 and 4, with every law's example).
  std::string example;
  /// Parses a table of this law (its own keys; `law` and `penalty_ratio` are the caller's);
  /// null when the parameters make it frictionless (a coefficient of 0).
  std::unique_ptr<FrictionLaw> (*parse)(const core::TomlView& table) = nullptr;
};

/// Every registered law, in the order the docs list them.
const std::vector<FrictionLawInfo>& friction_law_registry();
const FrictionLawInfo* find_friction_law(std::string_view name);
const std::vector<std::string>& friction_law_names();
/// The friction-law table of docs/scene.md (Markdown).
std::string friction_law_table_markdown();

}  // namespace c2d::constraints
