// Meshing of scene bodies through gmsh's C++ API, and reading of Gmsh .msh v4 files.
#pragma once

#include <optional>
#include <string>

#include "core/mesh.hpp"
#include "core/scene.hpp"

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

/// Meshes one body with T3 (order 1) or T6 (order 2) triangles. The result has one body (0) and
/// one material (0); its boundary is built, and named edge sets hold the primitive's edges
/// (rectangle: bottom, right, top, left; polygon: edge0..; disk: arc; disk_segment: arc, start,
/// end) or the .msh file's physical curves, and node sets its physical groups.
/// Throws InputError when gmsh rejects the geometry or the file, including when its meshing
/// fails (logged, never thrown inside gmsh's OpenMP loops, where it would terminate the process).
Mesh mesh_body(const BodySpec& body, int order);

/// Element size the body's refinement rules ask for at a point (global size when none applies):
/// h(d) = size + (growth - 1) * max(0, d - radius), the smallest over all rules.
double requested_size(const BodySpec& body, const Vec2& p);

}  // namespace c2d::core
