// Checks of a body's geometry and mesh request made before gmsh sees them: gmsh aborts the
// process on degenerate input (inside its threaded meshing, where no exception reaches us) and
// meshes without bound on tiny sizes, so both are refused here with the scene's location.
#pragma once

#include <string>
#include <vector>

#include "core/scene.hpp"

namespace c2d::core {

/// Why a polygon cannot bound a body (a repeated vertex, zero area, or two edges that cross or
/// touch away from their shared vertex); empty when it is a simple polygon.
std::string polygon_problem(const std::vector<Vec2>& points);

/// The signed area of a closed polygon (positive when counter-clockwise).
double signed_area(const std::vector<Vec2>& polygon);

/// The outline of a rectangle (its corners from min, counter-clockwise: the edges bottom, right,
/// top, left) or a polygon (its points); empty for other shapes.
std::vector<Vec2> polygon_outline(const ShapeSpec& s);

/// The area (less the holes) and the bounding-box diagonal of a shape (rectangle, polygon,
/// disk, disk segment, annulus); 0 for a point cloud.
double shape_area(const ShapeSpec& s);
double shape_diagonal(const ShapeSpec& s);

/// How many edges of length at most `size` the shape's boundary curves are cut into (at least
/// one per curve): a shape's triangles number at least this less two.
double boundary_segments(const ShapeSpec& s, double size);

/// About how many triangles gmsh makes for a body: its area over the uniform size (at least
/// the boundary's segments less two, the one layer of a strip thinner than the size), plus each
/// refinement's core disc (or strip) at its size and the graded zone where sizes grow by
/// `growth` per element back to the body's size. An estimate (within a factor of about 2),
/// for refusing requests far beyond the limit, not a prediction.
double estimate_elements(const BodySpec& body);

/// Memory a run takes per triangle, meshing to summary (measured: 2.3 M T3 triangles peaked at
/// 5.8 GB, about 2.5 kB each; rounded up).
constexpr double kBytesPerElement = 3000.0;

/// The default of analysis.max_elements: 2·10⁷, or what this machine's physical memory holds at
/// kBytesPerElement, whichever is smaller.
double default_max_elements();

}  // namespace c2d::core
