#include "constraints/friction_laws/coulomb_limited.hpp"

#include "constraints/friction_laws/coulomb.hpp"
#include "core/toml_view.hpp"

namespace c2d::constraints {

std::unique_ptr<FrictionLaw> CoulombLimited::parse(const core::TomlView& v) {
  const double mu = parse_friction_coefficient(v);
  const double tau = v["bound"].positive();
  return mu > 0 ? std::make_unique<CoulombLimited>(mu, tau) : nullptr;
}

}  // namespace c2d::constraints
