// Charts through gnuplot (PNG and SVG). A missing gnuplot is reported, not fatal.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "constraints/contact_set.hpp"
#include "core/model.hpp"
#include "core/scene.hpp"
#include "core/results.hpp"

namespace c2d::app {

/// The coordinate (0: x, 1: y) along which the points spread most: the abscissa for values
/// along a slave surface.
int spread_axis(const std::vector<Vec2>& points);

/// Label text as a gnuplot single-quoted literal: quotes doubled, control characters blanked.
/// Single-quoted strings are the only ones gnuplot substitutes nothing into (double-quoted
/// ones run `backquoted` commands), so every text from data goes into a script through this.
std::string gp_text(std::string_view text);

/// A file path as a gnuplot single-quoted literal, made absolute so that it never begins with
/// '<' or '|' (which gnuplot would run as a command). Throws InputError on a control character.
std::string gp_file(const std::string& path);

/// Runs gnuplot on a script (argument vector, no shell; output to SCRIPT.log, removed on
/// success); returns an empty string on success, else why it failed.
std::string run_gnuplot(const std::string& script_path);

/// Writes DIR/STEM.png and DIR/STEM.svg from gnuplot plot commands; "" or the failure reason.
std::string plot_png_and_svg(const std::string& dir, const std::string& stem,
                             const std::string& commands);

/// Recovered contact pressure along the slave surface, with the Hertz profile when the scene's
/// reference gives p_max and contact_length. Writes DIR/pressure.png and .svg.
std::string chart_contact_pressure(const std::string& dir, const constraints::ContactReport& c,
                                   const core::Scene& scene);

/// Deformed mesh (scaled) over the undeformed outline, coloured by smoothed von Mises.
/// Writes DIR/deformed.png and DIR/deformed.svg; returns "" or the failure reason.
std::string chart_deformed_mesh(const std::string& dir, const core::Model& model,
                                const core::Results& results);

}  // namespace c2d::app
