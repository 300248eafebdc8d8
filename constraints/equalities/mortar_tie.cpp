#include "constraints/equalities/mortar_tie.hpp"

#include "constraints/contact_scene.hpp"
#include "constraints/discretizations/mortar.hpp"
#include "core/errors.hpp"
#include "core/scene.hpp"

namespace c2d::constraints {

std::unique_ptr<EqualityConstraint> MortarTie::parse(const core::TomlView& v) {
  auto out = std::make_unique<MortarTie>();
  out->slave_ = core::parse_selection(v["slave"]);
  out->master_ = core::parse_selection(v["master"]);
  return out;
}

std::vector<EqualityRow> MortarTie::rows(const core::Model& model, int owner,
                                         const std::string& where) const {
  ContactPairSpec pair;
  pair.slave = slave_;
  pair.master = master_;
  pair.detection = "mortar";
  pair.where = where;
  const std::vector<Obstacle> none;
  const Mortar mortar({model, pair, none, -1});
  const auto coupling = mortar.coupling(model.mesh.nodes);
  if (coupling.empty())
    throw InputError(where + ": no part of the tie's slave surface faces its master surface");
  std::vector<EqualityRow> out;
  for (const auto& coefficients : coupling)
    for (int d = 0; d < 2; ++d) {
      EqualityRow row;
      row.owner = owner;
      for (const auto& [node, a] : coefficients) row.terms.emplace_back(2 * node + d, a);
      out.push_back(row);
    }
  return out;
}

}  // namespace c2d::constraints
