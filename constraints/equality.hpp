// How a [[constraint]] becomes equality rows on displacements (docs/scene.md): one class per
// type in constraints/equalities/, one line in the registry of equality.cpp. The scene parser
// asks the registry for the type named by `type`, which parses its own keys into an
// EqualityConstraint; EqualityConstraints asks each for its rows, and every method enforces them.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "core/model.hpp"
#include "core/toml_view.hpp"

namespace c2d::constraints {

/// One row of a multipoint constraint: Σ a_k u_k = rhs over full DOF indices k.
/// A row nonlinear in u (a rigid plate's in a load-stepped run) is its linearisation at a state
/// u*: terms = ∇c(u*), rhs = ∇c·u* − c(u*), and its second derivatives in `curvature`.
struct EqualityRow {
  std::vector<std::pair<int, double>> terms;
  double rhs = 0.0;
  int owner = -1;  ///< index of its [[constraint]]; -1 − p for the rows of [[plate]] p
  /// ∂²c/∂u_a∂u_b as (a, b, value), both orders listed; empty for a row linear in u.
  std::vector<std::tuple<int, int, double>> curvature;
};

/// A parsed [[constraint]] of one type.
class EqualityConstraint {
 public:
  virtual ~EqualityConstraint() = default;
  /// Its rows on the model, owned by constraint `owner`. Throws InputError (located by
  /// `where`) when its selections do not fit.
  virtual std::vector<EqualityRow> rows(const core::Model& model, int owner,
                                        const std::string& where) const = 0;
};

struct EqualityInfo {
  std::string name;     ///< the value of a [[constraint]]'s `type`
  std::string keys;     ///< its own keys, for the docs
  std::string summary;  ///< the rows it makes, for the docs
  std::vector<std::string> key_names;  ///< its own keys, for the parser
  /// Its keys in an example on two stacked blocks ("low" [0,2]×[0,1] below "up" [0,2]×[1,1.5]),
  /// with a zero right-hand side: the registry test runs every type's example.
  std::string example;
  /// Parses a table of this type (its own keys; the common ones are checked by the caller).
  std::unique_ptr<EqualityConstraint> (*parse)(const core::TomlView& table) = nullptr;
};

/// Every registered type, in the order the docs list them.
const std::vector<EqualityInfo>& equality_registry();
const EqualityInfo* find_equality(std::string_view name);
const std::vector<std::string>& equality_names();
/// The [[constraint]] table of docs/scene.md (Markdown).
std::string equality_table_markdown();

}  // namespace c2d::constraints
