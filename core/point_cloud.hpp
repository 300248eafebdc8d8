// A body given as a point cloud (shape type "points"): its boundary polygon and interior points,
// checked before gmsh triangulates them.
#pragma once

#include <vector>

#include "core/scene.hpp"

namespace c2d::core {

/// Twice the signed area of the triangle (o, a, b): positive when counter-clockwise.
double orientation(const Vec2& o, const Vec2& a, const Vec2& b);
/// Winding-number test of a point against a closed polygon (either orientation).
bool inside_polygon(const std::vector<Vec2>& polygon, const Vec2& q);

/// The checked point cloud of a `points` shape: its boundary polygon (given, else the convex
/// hull) with the cloud points on its edges inserted as vertices, and the interior points.
/// Throws InputError for fewer than 3 distinct points, duplicates, a collinear cloud, or points
/// outside the given boundary.
void split_point_cloud(const ShapeSpec& s, std::vector<Vec2>& boundary, std::vector<Vec2>& interior);

}  // namespace c2d::core
