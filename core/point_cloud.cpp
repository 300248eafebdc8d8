#include "core/point_cloud.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/errors.hpp"
#include "core/mesh_budget.hpp"

namespace c2d::core {

double orientation(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

namespace {

/// Convex hull, counter-clockwise, corners only (points on its edges are inserted afterwards).
/// Andrew's monotone chain, O(n log n).
std::vector<Vec2> convex_hull(std::vector<Vec2> p, double tol) {
  std::sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  std::vector<Vec2> h;
  for (int pass = 0; pass < 2; ++pass) {
    const size_t start = h.size();
    for (const Vec2& q : p) {
      while (h.size() >= start + 2 && orientation(h[h.size() - 2], h.back(), q) <= tol) h.pop_back();
      h.push_back(q);
    }
    h.pop_back();
    std::reverse(p.begin(), p.end());
  }
  return h;
}

}  // namespace

bool inside_polygon(const std::vector<Vec2>& polygon, const Vec2& q) {
  int winding = 0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Vec2 &a = polygon[i], &b = polygon[(i + 1) % polygon.size()];
    if (a.y() <= q.y()) {
      if (b.y() > q.y() && orientation(a, b, q) > 0) ++winding;
    } else if (b.y() <= q.y() && orientation(a, b, q) < 0) {
      --winding;
    }
  }
  return winding != 0;
}

/// The checked point cloud of a `points` shape: its boundary polygon (given, else the convex
/// hull) with the cloud points on its edges inserted as vertices, and the interior points.
/// Throws InputError for fewer than 3 distinct points, duplicates, a collinear cloud, or points
/// outside the given boundary.
void split_point_cloud(const ShapeSpec& s, std::vector<Vec2>& boundary, std::vector<Vec2>& interior) {
  Vec2 lo = Vec2::Constant(1e300), hi = Vec2::Constant(-1e300);
  for (const auto& q : s.points) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  for (const auto& q : s.boundary) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  const double size = (hi - lo).norm();
  const double tol = 1e-9 * size;
  std::vector<std::pair<Vec2, int>> sorted;
  for (size_t i = 0; i < s.points.size(); ++i) sorted.emplace_back(s.points[i], static_cast<int>(i));
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) {
    return a.first.x() < b.first.x() || (a.first.x() == b.first.x() && a.first.y() < b.first.y());
  });
  for (size_t i = 0; i < sorted.size(); ++i)
    for (size_t j = i + 1; j < sorted.size() && sorted[j].first.x() - sorted[i].first.x() <= tol; ++j)
      if ((sorted[j].first - sorted[i].first).norm() <= tol)
        throw InputError("shape.points: points " + std::to_string(std::min(sorted[i].second, sorted[j].second) + 1) +
                         " and " + std::to_string(std::max(sorted[i].second, sorted[j].second) + 1) +
                         " coincide; expected distinct points");
  std::vector<Vec2> polygon = s.boundary.empty() ? convex_hull(s.points, tol * size) : s.boundary;
  const double area = signed_area(polygon);
  if (2.0 * std::abs(area) <= 1e-12 * size * size)
    throw InputError(std::string(s.boundary.empty() ? "shape.points" : "shape.boundary") +
                     ": the points are collinear (no area to triangulate); expected a 2D cloud");
  if (area < 0) std::reverse(polygon.begin(), polygon.end());
  // Each cloud point: a polygon vertex, on a polygon edge (inserted there), inside, or outside.
  std::vector<std::vector<std::pair<double, Vec2>>> on_edge(polygon.size());
  for (size_t k = 0; k < s.points.size(); ++k) {
    const Vec2& q = s.points[k];
    bool placed = false;
    for (size_t i = 0; i < polygon.size() && !placed; ++i) {
      const Vec2 &a = polygon[i], &b = polygon[(i + 1) % polygon.size()];
      if ((q - a).norm() <= tol) {
        placed = true;
      } else if ((q - b).norm() > tol && std::abs(orientation(a, b, q)) <= tol * (b - a).norm()) {
        const double t = (q - a).dot(b - a) / (b - a).squaredNorm();
        if (t > 0 && t < 1) on_edge[i].emplace_back(t, q), placed = true;
      }
    }
    if (placed) continue;
    if (!inside_polygon(polygon, q))
      throw InputError("shape.points: point " + std::to_string(k + 1) + " (" + number_text(q.x()) +
                       ", " + number_text(q.y()) + ") lies outside the boundary polygon");
    interior.push_back(q);
  }
  for (size_t i = 0; i < polygon.size(); ++i) {
    boundary.push_back(polygon[i]);
    std::sort(on_edge[i].begin(), on_edge[i].end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [t, q] : on_edge[i]) boundary.push_back(q);
  }
}


}  // namespace c2d::core
