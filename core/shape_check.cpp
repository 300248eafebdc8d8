#include "core/shape_check.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "core/mesh_budget.hpp"
#include "core/point_cloud.hpp"

namespace c2d::core {

double distance_to_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

namespace {

/// A length for a message: 6 significant digits, exponent when small or large (1e-08).
std::string shown(double x) {
  std::ostringstream os;
  os << x;
  return os.str();
}

/// The first polygon feature thinner than `thinnest`: an edge that short, or a vertex that close
/// to an edge it is not on.
std::optional<std::string> thin_polygon_feature(const std::vector<Vec2>& p, double thinnest) {
  const size_t n = p.size();
  for (size_t i = 0; i < n; ++i) {
    const double length = (p[(i + 1) % n] - p[i]).norm();
    if (!(length >= thinnest))
      return "edge " + std::to_string(i + 1) + " of length " + shown(length);
  }
  for (size_t v = 0; v < n; ++v)
    for (size_t e = 0; e < n; ++e) {
      if (e == v || (e + 1) % n == v) continue;  // v is an end of edge e
      const double d = distance_to_segment(p[v], p[e], p[(e + 1) % n]);
      if (!(d >= thinnest))
        return "vertex " + std::to_string(v + 1) + " at " + shown(d) + " from edge " +
               std::to_string(e + 1);
    }
  return std::nullopt;
}

/// The first hole that leaves the shape, comes thinner than `thinnest` to its boundary or to
/// another hole, or is itself smaller than that.
std::optional<std::string> hole_problem(const ShapeSpec& s, double thinnest) {
  const std::vector<Vec2> outline = polygon_outline(s);
  for (size_t k = 0; k < s.holes.size(); ++k) {
    const ShapeSpec::Hole& h = s.holes[k];
    const std::string name = "hole " + std::to_string(k) + " (center " + shown(h.center.x()) +
                             ", " + shown(h.center.y()) + ", radius " + shown(h.radius) + ")";
    if (!(h.radius >= thinnest)) return name + " smaller than " + shown(thinnest);
    if (!inside_polygon(outline, h.center)) return name + " centred outside the shape";
    double wall = 1e300;
    for (size_t e = 0; e < outline.size(); ++e)
      wall = std::min(wall, distance_to_segment(h.center, outline[e], outline[(e + 1) % outline.size()]) - h.radius);
    if (!(wall >= thinnest)) return name + " at " + shown(wall) + " from the boundary";
    for (size_t j = 0; j < k; ++j) {
      const double gap = (h.center - s.holes[j].center).norm() - h.radius - s.holes[j].radius;
      if (!(gap >= thinnest)) return name + " at " + shown(gap) + " from hole " + std::to_string(j);
    }
  }
  return std::nullopt;
}

}  // namespace

std::optional<ShapeDefect> shape_defect(const ShapeSpec& s) {
  const double extent = shape_diagonal(s), thinnest = kThinnestFeature * extent;
  const std::string why = " (" + shown(kThinnestFeature) + " of its extent " + shown(extent) +
                          ": gmsh merges points closer than 1e-8 of the model's size)";
  // Far from the origin, a small shape's points lose their digits (a disk of radius 1e-5 at
  // x = 1000 was meshed with 31 nodes instead of 89).
  double farthest = 0.0;
  for (const auto& p : s.type == "polygon" ? s.points : s.boundary)
    farthest = std::max(farthest, p.cwiseAbs().maxCoeff());
  if (s.type == "rectangle")
    farthest = std::max(s.min.cwiseAbs().maxCoeff(), s.max.cwiseAbs().maxCoeff());
  if (s.type == "disk" || s.type == "disk_segment" || s.type == "annulus")
    farthest = s.center.cwiseAbs().maxCoeff() + s.radius;
  if (s.type != "points" && !(extent >= kThinnestFeature * farthest)) {
    const std::string key = s.type == "rectangle" ? "min"
                            : s.type == "polygon" ? "points"
                                                  : "center";
    return ShapeDefect{key, "expected a shape whose extent is at least " + shown(kThinnestFeature) +
                                " of its distance from the origin " + shown(farthest) +
                                " (gmsh loses its points' digits), found " + shown(extent)};
  }
  if (s.type == "rectangle") {
    const double thickness = (s.max - s.min).minCoeff();
    if (!(thickness >= thinnest))
      return ShapeDefect{"max", "expected a rectangle thicker than " + shown(thinnest) + why +
                                    ", found " + shown(thickness)};
  } else if (s.type == "polygon" || (s.type == "points" && !s.boundary.empty())) {
    const std::vector<Vec2>& polygon = s.type == "polygon" ? s.points : s.boundary;
    ShapeSpec outline;
    outline.type = "polygon";
    outline.points = polygon;
    const double polygon_thinnest = kThinnestFeature * shape_diagonal(outline);
    if (const auto feature = thin_polygon_feature(polygon, polygon_thinnest))
      return ShapeDefect{s.type == "polygon" ? "points" : "boundary",
                         "expected a polygon with no feature thinner than " +
                             shown(polygon_thinnest) + why + ", found " + *feature};
  }
  if (!s.holes.empty())
    if (const auto problem = hole_problem(s, thinnest))
      return ShapeDefect{"holes", "expected circular holes inside the shape, each at least " +
                                      shown(thinnest) + " from its boundary and from the others" +
                                      why + ", found " + *problem};
  if (s.type == "annulus") {
    const double wall = s.radius - s.inner_radius;
    if (!(wall >= thinnest))
      return ShapeDefect{"inner_radius", "expected an annulus whose wall is thicker than " +
                                             shown(thinnest) + why + ", found " + shown(wall)};
  } else if (s.type == "disk_segment") {
    // The thinnest part of a wedge is at its arc: the arc's end to the other straight edge is
    // r sin(angle) for an opening (or a gap left to 360 degrees) below 90 degrees.
    const double opening = s.to_deg - s.from_deg;
    const double full = 360.0 - 1e-9;  // build_geometry meshes a full disk from here
    const double narrowest = std::min({opening, 360.0 - opening, 90.0});
    if (opening < full && !(s.radius * std::sin(narrowest * std::numbers::pi / 180.0) >= thinnest))
      return ShapeDefect{"to_deg",
                         "expected a disk segment whose opening and gap to 360 "
                         "degrees are wider than " +
                             shown(thinnest) + why + " at its radius, found " + shown(opening) +
                             " degrees"};
  }
  return std::nullopt;
}

}  // namespace c2d::core
