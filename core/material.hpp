// Isotropic linear elastic material in plane stress or plane strain.
#pragma once

#include <string>

#include "core/types.hpp"

namespace c2d::core {

enum class PlaneState { kPlaneStress, kPlaneStrain };

struct Material {
  std::string name;
  double young = 0.0;      ///< E
  double poisson = 0.0;    ///< nu
  double thickness = 1.0;  ///< out-of-plane thickness t (plane strain: usually 1)
  PlaneState state = PlaneState::kPlaneStress;

  /// Constitutive matrix D with sigma = D eps, Voigt order [xx, yy, xy], engineering shear.
  Mat3 elasticity() const;
  /// D^{-1}, the compliance used by energy norms.
  Mat3 compliance() const;
  /// Out-of-plane stress sigma_zz implied by an in-plane stress (zero in plane stress).
  double sigma_zz(const Voigt& s) const;
};

/// Von Mises equivalent stress including sigma_zz.
double von_mises(const Voigt& s, double szz);
/// Principal in-plane stresses (s1 >= s2).
Eigen::Vector2d principal(const Voigt& s);

}  // namespace c2d::core
