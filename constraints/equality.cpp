#include "constraints/equality.hpp"

#include "constraints/equalities/equal_component.hpp"
#include "constraints/equalities/linear_rows.hpp"
#include "constraints/equalities/mortar_tie.hpp"
#include "constraints/registry.hpp"

namespace c2d::constraints {

const std::vector<EqualityInfo>& equality_registry() {
  static const std::vector<EqualityInfo> registry = {
      {"linear", "`terms = [ { on, dof, coefficient }, ... ]`, `value` (default 0)", "Σ aᵢ u_{nᵢ,dᵢ} = value; each term's `on` selects one node, `dof` is `ux` or `uy`", {"terms", "value"},
       "terms = [ { on = { nearest = [0.0, 1.5] }, dof = \"uy\", coefficient = 1.0 },\n"
       "          { on = { nearest = [2.0, 1.5] }, dof = \"uy\", coefficient = -1.0 } ]",
       &LinearRows::parse},
      {"equal", "`on` (two nodes or more), `dof`", "every selected node shares u_dof: u_k − u_first = 0", {"on", "dof"},
       "on = { body = \"up\", edge = \"top\" }\ndof = \"uy\"", &EqualComponent::parse},
      {"tie", "`slave`, `master` (boundary edges)", "the slave surface moves with the master surface, in x and y: mortar tying in the reference configuration (per slave corner node j, ∫Φⱼ u_slave ds = ∫Φⱼ u_master ds), so a uniform traction crosses non-matching meshes exactly", {"slave", "master"},
       "slave = { body = \"up\", edge = \"bottom\" }\nmaster = { body = \"low\", edge = \"top\" }",
       &MortarTie::parse},
  };
  return registry;
}

const EqualityInfo* find_equality(std::string_view name) {
  return find_entry(equality_registry(), name);
}

const std::vector<std::string>& equality_names() {
  static const std::vector<std::string> names = entry_names(equality_registry());
  return names;
}

std::string equality_table_markdown() {
  std::string out = "| `type` | keys | rows |\n|---|---|---|\n";
  for (const auto& e : equality_registry())
    out += "| `" + e.name + "` | " + e.keys + " | " + e.summary + " |\n";
  return out;
}

}  // namespace c2d::constraints
