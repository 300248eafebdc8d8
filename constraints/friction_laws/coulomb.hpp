// `law = "coulomb"`: the friction force at most μ × the normal force.
#pragma once

#include "constraints/friction_law.hpp"

namespace c2d::constraints {

/// A table's `coefficient`: a friction coefficient, finite and ≥ 0 (the Coulomb laws').
double parse_friction_coefficient(const core::TomlView& v);

class Coulomb final : public FrictionLaw {
 public:
  explicit Coulomb(double mu) : mu_(mu) {}
  static std::unique_ptr<FrictionLaw> parse(const core::TomlView& v);
  FrictionBound bound(double, double) const override { return {0.0, mu_, 0}; }

 private:
  double mu_;
};

}  // namespace c2d::constraints
