// `law = "tresca"`: the friction force at most a fixed shear traction τ times the row's share of
// the slave surface, closed or not.
#pragma once

#include "constraints/friction_law.hpp"

namespace c2d::constraints {

class Tresca final : public FrictionLaw {
 public:
  explicit Tresca(double tau) : tau_(tau) {}
  static std::unique_ptr<FrictionLaw> parse(const core::TomlView& v);
  FrictionBound bound(double, double area) const override { return {tau_ * area, 0.0, 0}; }

 private:
  double tau_;
};

}  // namespace c2d::constraints
