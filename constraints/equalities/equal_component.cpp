#include "constraints/equalities/equal_component.hpp"

#include "core/errors.hpp"
#include "core/scene.hpp"

namespace c2d::constraints {

std::unique_ptr<EqualityConstraint> EqualComponent::parse(const core::TomlView& v) {
  auto out = std::make_unique<EqualComponent>();
  out->on_ = core::parse_selection(v["on"]);
  out->dof_ = v["dof"].choice({"ux", "uy"}) == "ux" ? 0 : 1;
  return out;
}

std::vector<EqualityRow> EqualComponent::rows(const core::Model& model, int owner,
                                              const std::string& where) const {
  const std::vector<int> nodes = core::select_nodes(model, on_);
  if (nodes.size() < 2)
    throw InputError(where + ": `on` must select at least two nodes to share u" +
                     (dof_ == 0 ? "x" : "y") + ", it selects " + std::to_string(nodes.size()));
  std::vector<EqualityRow> out;
  for (size_t k = 1; k < nodes.size(); ++k)
    out.push_back({{{2 * nodes[k] + dof_, 1.0}, {2 * nodes[0] + dof_, -1.0}}, 0.0, owner, {}});
  return out;
}

}  // namespace c2d::constraints
