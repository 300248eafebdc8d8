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

/// `v` to `digits` significant digits as a reader writes it ("0.739", "214", "2000",
/// "1.5e-05").
std::string rounded_text(double v, int digits = 3);
/// rounded_text with the unit, if named: "214 MPa".
inline std::string quantity_text(double v, const std::string& u, int digits = 3) {
  return rounded_text(v, digits) + unit_suffix(u);
}

}  // namespace c2d::app
