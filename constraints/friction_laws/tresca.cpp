#include "constraints/friction_laws/tresca.hpp"

#include "core/toml_view.hpp"

namespace c2d::constraints {

std::unique_ptr<FrictionLaw> Tresca::parse(const core::TomlView& v) {
  return std::make_unique<Tresca>(v["bound"].positive());
}

}  // namespace c2d::constraints
