#include "constraints/equalities/linear_rows.hpp"

#include <cmath>

#include "core/errors.hpp"
#include "core/scene.hpp"

namespace c2d::constraints {

std::unique_ptr<EqualityConstraint> LinearRows::parse(const core::TomlView& v) {
  auto out = std::make_unique<LinearRows>();
  for (const auto& t : v["terms"].tables()) {
    t.check_keys({"on", "dof", "coefficient"});
    Term term;
    term.on = core::parse_selection(t["on"]);
    term.dof = t["dof"].choice({"ux", "uy"}) == "ux" ? 0 : 1;
    term.coefficient = t["coefficient"].number();
    // As loads: beyond 1e30 (or below 1e-30) a row's products overflow or vanish in K.
    if (!(std::abs(term.coefficient) >= 1e-30 && std::abs(term.coefficient) <= 1e30))
      t["coefficient"].fail("a non-zero coefficient between 1e-30 and 1e30 in magnitude");
    out->terms_.push_back(term);
  }
  if (out->terms_.empty()) v["terms"].fail("at least one term { on, dof, coefficient }");
  out->value_ = v["value"].number_or(0.0);
  if (!(std::abs(out->value_) <= 1e30)) v["value"].fail("a value of at most 1e30 in magnitude");
  return out;
}

std::vector<EqualityRow> LinearRows::rows(const core::Model& model, int owner,
                                          const std::string& where) const {
  EqualityRow row;
  row.owner = owner;
  row.rhs = value_;
  for (const Term& t : terms_) {
    const std::vector<int> nodes = core::select_nodes(model, t.on);
    if (nodes.size() != 1)
      throw InputError(where + ": each term's `on` must select one node, it selects " +
                       std::to_string(nodes.size()));
    row.terms.emplace_back(2 * nodes[0] + t.dof, t.coefficient);
  }
  return {row};
}

}  // namespace c2d::constraints
