#include "constraints/friction_law.hpp"

#include "constraints/friction_laws/coulomb.hpp"
#include "constraints/friction_laws/coulomb_limited.hpp"
#include "constraints/friction_laws/tresca.hpp"
#include "constraints/registry.hpp"

namespace c2d::constraints {

const std::vector<FrictionLawInfo>& friction_law_registry() {
  static const std::vector<FrictionLawInfo> registry = {
      {"coulomb", "`coefficient` = μ ≥ 0", "abs(λ_t) ≤ μ λ_n: the shear traction at most μ × the pressure", {"coefficient"}, false,
       "coefficient = 0.3", &Coulomb::parse},
      {"tresca", "`bound` = τ > 0 (force per area)", "abs(λ_t) ≤ τ × the row's share of the slave surface, whether the row is closed or not (the classical Tresca problem)", {"bound"}, true,
       "bound = 0.5", &Tresca::parse},
      {"coulomb_limited", "`coefficient` = μ ≥ 0, `bound` = τ > 0", "Coulomb with a shear limit: the shear traction at most min(μ × the pressure, τ), as in metal forming, where the shear cannot exceed the softer body's shear strength", {"coefficient", "bound"}, true,
       "coefficient = 0.3\nbound = 0.5", &CoulombLimited::parse},
  };
  return registry;
}

const FrictionLawInfo* find_friction_law(std::string_view name) {
  return find_entry(friction_law_registry(), name);
}

const std::vector<std::string>& friction_law_names() {
  static const std::vector<std::string> names = entry_names(friction_law_registry());
  return names;
}

std::string friction_law_table_markdown() {
  std::string out = "| `law` | keys | bound |\n|---|---|---|\n";
  for (const auto& e : friction_law_registry())
    out += "| `" + e.name + "` | " + e.keys + " | " + e.summary + " |\n";
  return out;
}

}  // namespace c2d::constraints
