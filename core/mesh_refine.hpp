// A triangle mesh whose boundary segments remember their curve, refined by subdivision:
// meshing a large body coarse and splitting each triangle into four by its edge midpoints costs
// a fraction of meshing it fine (gmsh spends about 50 µs per triangle; a subdivision, 0.2 µs),
// keeps every angle of the coarse mesh (the children are similar to their parent), and puts
// the new boundary nodes on the curves, as a fine mesh of the same sizes would have them.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "core/mesh.hpp"

namespace c2d::core {

/// #nodes points, #elements triangles (T3: the first 3 entries; T6: corners counter-clockwise
/// or not, then the mid-sides of edges 0-1, 1-2, 2-0), and the boundary segments of named
/// curves as (end node a, end node b, curve index).
struct CurveMesh {
  int order = 1;
  std::vector<Vec2> nodes;
  std::vector<std::array<int, 6>> elements;
  std::vector<std::array<int, 3>> segments;
};

/// Moves a point that lies near curve `curve` (the midpoint of one of its chords) onto it.
using CurveProjector = std::function<void(int curve, Vec2& p)>;

/// Splits every triangle of a T3 mesh into four by its edge midpoints and every segment into two;
/// a segment's midpoint is moved onto its curve.
void subdivide(CurveMesh& mesh, const CurveProjector& project);

/// Turns a T3 mesh into T6: one mid-side node per edge, on the curve for a segment's edge.
void make_quadratic(CurveMesh& mesh, const CurveProjector& project);

/// Renumbers the nodes along a Z-order (Morton) curve of their coordinates and orders the
/// elements by their smallest node: nodes close in the mesh become close in memory, which the
/// assembly, the factorisation's analysis and the recovery loops read faster.
void renumber_spatially(CurveMesh& mesh);

/// The Mesh (one body, material 0): elements counter-clockwise, boundary built, and the
/// boundary edges of segments of curve i in edge group curve_names[i].
Mesh to_mesh(CurveMesh&& mesh, const std::vector<std::string>& curve_names);

/// Below 4 times this many triangles a body is meshed by gmsh alone; above, gmsh meshes it with
/// sizes 2^k times larger, keeping at least this many triangles (enough to resolve the shape and
/// the grading of its refinements), and k subdivisions give the requested sizes.
constexpr double kCoarseElements = 15000.0;

/// How many times to subdivide a mesh of about `elements` triangles so that the mesh gmsh makes
/// keeps at least `coarse_elements` of them (enough to resolve the shape and its grading).
int subdivision_levels(double elements, double coarse_elements);

}  // namespace c2d::core
