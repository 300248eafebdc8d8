// `law = "coulomb_limited"`: Coulomb with a shear limit, the friction force at most
// min(μ λ_n, τ × the row's share of the slave surface); two pieces, Coulomb's below the
// pressure τ/μ and a Tresca cap above it.
#pragma once

#include "constraints/friction_law.hpp"

namespace c2d::constraints {

class CoulombLimited final : public FrictionLaw {
 public:
  CoulombLimited(double mu, double tau) : mu_(mu), tau_(tau) {}
  static std::unique_ptr<FrictionLaw> parse(const core::TomlView& v);
  FrictionBound bound(double normal_force, double area) const override {
    if (mu_ * normal_force < tau_ * area) return {0.0, mu_, 0};
    return {tau_ * area, 0.0, 1};
  }

 private:
  double mu_, tau_;
};

}  // namespace c2d::constraints
