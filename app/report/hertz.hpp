// Hertz's contact pressure, the analytic reference of the cylinder scenes, in one place: the
// scene's [reference] values, the profile p0 √(1 − (x/b)²), its error against a computed profile,
// the same form fitted to nodal pressures, and the curve drawn beside them.
#pragma once

#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "core/scene.hpp"

namespace c2d::app {

/// Hertz's peak pressure p0 and contact half-width b.
struct HertzReference {
  double p0 = 0.0, b = 0.0;
};

/// The scene's Hertz reference: a [reference] whose kind starts with "hertz" and which gives
/// p_max and contact_length; nullopt otherwise.
std::optional<HertzReference> hertz_reference(const core::Scene& scene);

/// A Cattaneo–Mindlin reference: Hertz's p0 and b with the coefficient μ and the stick zone's
/// half-width c.
struct CattaneoReference {
  HertzReference hertz;
  double mu = 0.0, c = 0.0;
};

/// The scene's Cattaneo–Mindlin reference: kind "cattaneo_mindlin" with p_max (p0),
/// contact_length (2b), stick_length (2c) and coefficient (μ); nullopt otherwise.
std::optional<CattaneoReference> cattaneo_reference(const core::Scene& scene);

/// Relative L2 error of a pressure profile against Hertz's p0 √(1 − x²/b²) over the sampled
/// range |x| ≤ 1.5 b within the nodes' span (linear interpolation between sorted nodes;
/// x measured along the surface's main direction from the reference's centre at 0).
double hertz_profile_error(const std::vector<std::pair<double, double>>& x_p, double p0, double b);

/// The interior of the contact zone, as a fraction of b: hertz_inner_profile_error's window.
inline constexpr double kInnerWindow = 0.9;

/// The same measure over |x| ≤ 0.9 b only, relative to Hertz's profile there: the error of the
/// pressure where it is smooth. Over [0, 1.5 b] the √(b − |x|) edge dominates any piecewise-linear
/// profile: its error is of order h/b with a constant set by where b falls between two nodes, so
/// that even Hertz's exact pressure sampled at a run's nodes scores 0.46, 0.17, 0.23 % on the
/// elastic block's three compare levels. Inside 0.9 b the error of a consistent method falls as
/// h² or faster; the edge's position is the contact length's error.
double hertz_inner_profile_error(const std::vector<std::pair<double, double>>& x_p, double p0,
                                 double b);

/// The same measure for the shear traction of the Cattaneo–Mindlin problem (Johnson §7.1): a
/// Hertz contact of half-width b and peak p0 under a tangential force Q < μP, stick over |x| < c
/// with c = b √(1 − Q/μP): q(x) = μ p0 √(1 − x²/b²) − μ p0 (c/b) √(1 − x²/c²) (the last term for
/// |x| < c only). `x_q` holds the shear magnitude in the direction of the force.
double cattaneo_mindlin_error(const std::vector<std::pair<double, double>>& x_q, double mu,
                              double p0, double b, double c);

struct HertzFit {
  bool ok = false;
  double p0 = 0.0, b = 0.0, x0 = 0.0;
  int iterations = 0;
  std::string message;
};

/// Fits p0 √(1 − ((x − x0)/b)²) (zero outside |x − x0| < b) to nodal pressures by nonlinear
/// least squares (Ceres), so the contact width does not depend on where the nodes fall. x0 is
/// fixed at 0 when the nodes lie on one side of it (a symmetric half model). Starts from the
/// largest pressure and the extent of the positive ones.
HertzFit fit_hertz_profile(const std::vector<std::pair<double, double>>& x_p);

/// gnuplot: the x range of data spanning [lo, hi] within 1.6 half-widths of the centre, and
/// dense sampling for the curve. Numbers in the stream's precision.
void write_hertz_window(std::ostream& gp, const HertzReference& hertz, double lo, double hi);

/// gnuplot: Hertz's profile as a function of x, zero outside |x| < b. Numbers in the stream's
/// precision.
void write_hertz_curve(std::ostream& gp, const HertzReference& hertz);

}  // namespace c2d::app
