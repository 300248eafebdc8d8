// Meshing of scene bodies through gmsh's C++ API, and reading of Gmsh .msh v4 files.
#pragma once

#include <optional>
#include <string>

#include "core/mesh.hpp"
#include "core/scene.hpp"

namespace c2d::core {

/// Meshes one body with T3 (order 1) or T6 (order 2) triangles. The result has one body (0) and
/// one material (0); its boundary is built, and named edge sets hold the primitive's edges
/// (rectangle: bottom, right, top, left; polygon: edge0..; disk: arc; disk_segment: arc, start,
/// end; annulus: outer, inner) or the .msh file's physical curves, and node sets its physical groups.
/// Throws InputError when gmsh rejects the geometry or the file, including when its meshing
/// fails (logged, never thrown inside gmsh's OpenMP loops, where it would terminate the process).
Mesh mesh_body(const BodySpec& body, int order);

/// Element size the body's refinement rules ask for at a point (global size when none applies):
/// h(d) = size + (growth - 1) * max(0, d - radius), the smallest over all rules.
double requested_size(const BodySpec& body, const Vec2& p);

}  // namespace c2d::core
