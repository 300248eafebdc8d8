#include "core/material.hpp"

#include <cmath>

namespace c2d::core {

Mat3 Material::elasticity() const {
  Mat3 d = Mat3::Zero();
  const double e = young, nu = poisson;
  if (state == PlaneState::kPlaneStress) {
    const double c = e / (1.0 - nu * nu);
    d << c, c * nu, 0.0, c * nu, c, 0.0, 0.0, 0.0, c * (1.0 - nu) / 2.0;
  } else {
    const double c = e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
    const double r = nu / (1.0 - nu);
    d << c, c * r, 0.0, c * r, c, 0.0, 0.0, 0.0, e / (2.0 * (1.0 + nu));
  }
  return d;
}

Mat3 Material::compliance() const {
  Mat3 c = Mat3::Zero();
  const double e = young, nu = poisson;
  if (state == PlaneState::kPlaneStress) {
    c << 1.0, -nu, 0.0, -nu, 1.0, 0.0, 0.0, 0.0, 2.0 * (1.0 + nu);
    c /= e;
  } else {
    c << 1.0 - nu, -nu, 0.0, -nu, 1.0 - nu, 0.0, 0.0, 0.0, 2.0;
    c *= (1.0 + nu) / e;
  }
  return c;
}

double Material::sigma_zz(const Voigt& s) const {
  return state == PlaneState::kPlaneStrain ? poisson * (s[0] + s[1]) : 0.0;
}

double von_mises(const Voigt& s, double szz) {
  const double sx = s[0], sy = s[1], txy = s[2];
  const double v = sx * sx + sy * sy + szz * szz - sx * sy - sy * szz - szz * sx + 3.0 * txy * txy;
  return std::sqrt(std::max(v, 0.0));
}

Eigen::Vector2d principal(const Voigt& s) {
  const double c = 0.5 * (s[0] + s[1]);
  const double r = std::hypot(0.5 * (s[0] - s[1]), s[2]);
  return {c + r, c - r};
}

}  // namespace c2d::core
