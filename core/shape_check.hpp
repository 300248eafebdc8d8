// Whether gmsh can mesh a shape reliably: the geometric checks the scene parser runs on every
// shape before anything is meshed (features too thin for gmsh's tolerance, shapes too small for
// their distance from the origin).
#pragma once

#include <optional>
#include <string>

#include "core/scene.hpp"
#include "core/types.hpp"

namespace c2d::core {

/// The thinnest feature a shape may have, as a fraction of its extent (the diagonal of its
/// bounding box, a disk's diameter). gmsh merges points closer than its Geometry.Tolerance
/// (1e-8) times the model's size and then cannot recover the boundary: it failed on rectangles
/// from a thickness of 1e-9 of their length, at any element size. 1e-6 leaves it a margin.
constexpr double kThinnestFeature = 1e-6;

/// A shape gmsh cannot mesh reliably: the key of the shape table at fault (min, max, points,
/// boundary, center, to_deg) and "expected ..., found ..." for the message.
struct ShapeDefect {
  std::string key;
  std::string message;
};

/// Why gmsh cannot mesh this shape reliably, if it cannot: a rectangle thinner than
/// kThinnestFeature of its extent, a polygon with an edge that short or a vertex that close to
/// an edge it is not on (thin triangles, spikes, near-collinear or nearly touching edges), a
/// disk segment whose opening or gap is that thin, or a shape smaller than kThinnestFeature of
/// its distance from the origin. Polygons must already be simple (polygon_problem). The scene
/// parser refuses these; mesh_body does not check again.
std::optional<ShapeDefect> shape_defect(const ShapeSpec& shape);

/// The distance from p to the segment [a, b] (to a when the segment is a point).
double distance_to_segment(const Vec2& p, const Vec2& a, const Vec2& b);

}  // namespace c2d::core
