#include "constraints/friction_laws/coulomb.hpp"

#include "core/toml_view.hpp"

namespace c2d::constraints {

double parse_friction_coefficient(const core::TomlView& v) {
  const double mu = v["coefficient"].number();
  if (!(mu >= 0 && mu <= 1e6)) v["coefficient"].fail("a friction coefficient >= 0");
  return mu;
}

std::unique_ptr<FrictionLaw> Coulomb::parse(const core::TomlView& v) {
  const double mu = parse_friction_coefficient(v);
  return mu > 0 ? std::make_unique<Coulomb>(mu) : nullptr;
}

}  // namespace c2d::constraints
