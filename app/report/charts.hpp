// The charts `contact2d run` draws of its own results (PNG and SVG through gnuplot).
#pragma once

#include <string>

#include <Eigen/Geometry>

#include "constraints/contact_detection.hpp"
#include "constraints/contact_set.hpp"
#include "core/model.hpp"
#include "core/results.hpp"
#include "core/scene.hpp"

namespace c2d::app {

/// Recovered contact pressure along the slave surface, with the Hertz profile when the scene's
/// reference gives p_max and contact_length. Writes DIR/pressure.png and .svg.
std::string chart_contact_pressure(const std::string& dir, const constraints::ContactReport& c,
                                   const core::Scene& scene);

/// The window of the deformed mesh: for a model wider than three times its height (its box,
/// deformed and undeformed), x and y ranges that widen y about it to a third of the width, so
/// that the equal-scale plot keeps room for its colour bar's ticks; "" for other shapes.
std::string slender_window(const Eigen::AlignedBox2d& box);

/// Deformed mesh over the undeformed outline, coloured by smoothed von Mises: at true scale for
/// finite strain (`finite_strain`, the scene's geometric nonlinearity), else magnified by
/// displacement_scale. Axes labelled with the length and stress units the scene's `units`
/// names (empty: none). Writes DIR/deformed.png and DIR/deformed.svg; "" or the failure reason.
std::string chart_deformed_mesh(const std::string& dir, const core::Model& model,
                                const core::Results& results, const std::string& units = "",
                                bool finite_strain = false);

/// The contact zone: von Mises under the surface in a square window of three contact lengths
/// around the active slave nodes (Hertz's subsurface maximum, at 0.70 b, shows), drawn at true
/// scale (the converged state: bodies in contact do not cross, as a magnified deformation
/// would make them), the rigid obstacles in black where they are; from the run's VTU
/// `vtu_path`. Writes DIR/contact_zone.png and .svg; "" without active contact (nothing
/// drawn) or on success, else the failure.
std::string chart_contact_zone(const std::string& dir, const std::string& vtu_path,
                               const constraints::ContactReport& c,
                               const std::vector<constraints::Obstacle>& obstacles,
                               const std::vector<Vec2>& mesh_nodes,
                               const core::Results& results, const std::string& units);

}  // namespace c2d::app
