// The units a scene names in its free-text `units` ("N, mm, MPa"): each token recognised by its
// form (…Pa, psi, ksi or x/m² a stress; m, mm, cm, km, um, in, ft a length; …N, lbf, kip, t, kgf
// a force); what is not recognised stays unnamed. For the terminal summary and chart labels.
#pragma once

#include <string>

namespace c2d::app {

struct Units {
  std::string force, length, stress;
};

Units parse_units(const std::string& text);

/// " unit" (terminal) or "" when the unit is unnamed.
inline std::string unit_suffix(const std::string& u) { return u.empty() ? "" : " " + u; }
/// "label [unit]" (axes) or "label" when the unit is unnamed.
inline std::string axis_label(const std::string& label, const std::string& u) {
  return u.empty() ? label : label + " [" + u + "]";
}

}  // namespace c2d::app
