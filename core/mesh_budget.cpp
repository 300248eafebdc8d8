#include "core/mesh_budget.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace c2d::core {

namespace {

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// Whether segments ab and cd share a point (collinear overlaps included).
bool segments_meet(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double d1 = cross(b - a, c - a), d2 = cross(b - a, d - a);
  const double d3 = cross(d - c, a - c), d4 = cross(d - c, b - c);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
    return true;
  auto on = [](const Vec2& p, const Vec2& q, const Vec2& r, double c) {
    return c == 0 && std::min(p.x(), q.x()) <= r.x() && r.x() <= std::max(p.x(), q.x()) &&
           std::min(p.y(), q.y()) <= r.y() && r.y() <= std::max(p.y(), q.y());
  };
  return on(a, b, c, d1) || on(a, b, d, d2) || on(c, d, a, d3) || on(c, d, b, d4);
}

/// The diagonal of the points' bounding box.
double diagonal(const std::vector<Vec2>& p) {
  Vec2 lo = Vec2::Constant(1e300), hi = Vec2::Constant(-1e300);
  for (const auto& q : p) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  return (hi - lo).norm();
}

}  // namespace

double signed_area(const std::vector<Vec2>& p) {
  double a = 0.0;
  for (size_t i = 0; i < p.size(); ++i) a += cross(p[i], p[(i + 1) % p.size()]);
  return 0.5 * a;
}

std::string polygon_problem(const std::vector<Vec2>& p) {
  const size_t n = p.size();
  const double diag = diagonal(p);
  for (size_t i = 0; i < n; ++i)
    if ((p[(i + 1) % n] - p[i]).norm() <= 1e-12 * diag)
      return "vertex " + std::to_string(i + 1) + " repeats vertex " + std::to_string((i + 1) % n + 1);
  // Non-adjacent edges must not meet (a polygon has a few dozen vertices: pairs are cheap).
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j) {
      if (j == i + 1 || (i == 0 && j == n - 1)) continue;
      if (segments_meet(p[i], p[(i + 1) % n], p[j], p[(j + 1) % n]))
        return "edges " + std::to_string(i + 1) + " and " + std::to_string(j + 1) +
               " meet (the polygon intersects itself)";
    }
  if (!(std::abs(signed_area(p)) > 1e-12 * diag * diag)) return "the polygon has no area (collinear points)";
  return {};
}

std::vector<Vec2> polygon_outline(const ShapeSpec& s) {
  if (s.type == "rectangle") return {s.min, {s.max.x(), s.min.y()}, s.max, {s.min.x(), s.max.y()}};
  if (s.type == "polygon") return s.points;
  return {};
}

namespace {

/// A polygon edge drawn as an arc: its opening angle, and the area between it and its chord,
/// positive where the arc bulges out of the polygon.
struct ArcPiece {
  double angle = 0.0, bulge = 0.0;
};

ArcPiece arc_piece(const ShapeSpec& s, const ShapeSpec::Arc& arc) {
  const size_t n = s.points.size();
  const Vec2 a = s.points[arc.edge], b = s.points[(arc.edge + 1) % n];
  const Vec2 from = a - arc.center, to = b - arc.center;
  ArcPiece piece;
  piece.angle = angle_between(from, to);
  const double r = arc.radius;
  const double segment = 0.5 * r * r * (piece.angle - std::sin(piece.angle));
  // The minor arc's middle lies from the centre towards the chord's middle.
  const Vec2 towards = 0.5 * (a + b) - arc.center;
  const Vec2 middle =
      arc.center + r * (towards.norm() > 0 ? Vec2(towards.normalized()) : Vec2::UnitX());
  const Vec2 chord = b - a, off = middle - a;
  const double side = chord.x() * off.y() - chord.y() * off.x();  // > 0: left of the chord
  const bool outward = (side > 0) != (signed_area(s.points) > 0);
  piece.bulge = outward ? segment : -segment;
  return piece;
}

}  // namespace

double shape_area(const ShapeSpec& s) {
  auto disk = [](double r) { return std::numbers::pi * r * r; };
  double holes = 0.0;
  for (const auto& h : s.holes) holes += disk(h.radius);
  if (s.type == "rectangle") return (s.max - s.min).prod() - holes;
  if (s.type == "polygon") {
    double area = std::abs(signed_area(s.points)) - holes;
    for (const auto& arc : s.arcs) area += arc_piece(s, arc).bulge;
    return area;
  }
  if (s.type == "disk") return disk(s.radius);
  if (s.type == "annulus") return disk(s.radius) - disk(s.inner_radius);
  if (s.type == "disk_segment") return 0.5 * s.radius * s.radius * (s.to_deg - s.from_deg) * std::numbers::pi / 180.0;
  return 0.0;
}

double shape_diagonal(const ShapeSpec& s) {
  if (s.type == "rectangle") return (s.max - s.min).norm();
  if (s.type == "polygon" || s.type == "points") return diagonal(s.points);
  return 2.0 * s.radius;
}

double boundary_segments(const ShapeSpec& s, double size) {
  auto pieces = [size](double length) { return std::max(1.0, std::ceil(length / size)); };
  auto circle = [&](double r) { return std::max(3.0, pieces(2.0 * std::numbers::pi * r)); };
  double n = 0.0;
  if (s.type == "rectangle") {
    const Vec2 d = s.max - s.min;
    n = 2.0 * (pieces(std::abs(d.x())) + pieces(std::abs(d.y())));
  } else if (s.type == "polygon") {
    std::vector<double> length(s.points.size());
    for (size_t i = 0; i < s.points.size(); ++i)
      length[i] = (s.points[(i + 1) % s.points.size()] - s.points[i]).norm();
    for (const auto& arc : s.arcs) length[arc.edge] = arc.radius * arc_piece(s, arc).angle;
    for (double l : length) n += pieces(l);
  } else if (s.type == "disk") {
    n = circle(s.radius);
  } else if (s.type == "annulus") {
    n = circle(s.radius) + circle(s.inner_radius);
  } else if (s.type == "disk_segment") {
    n = pieces(s.radius * (s.to_deg - s.from_deg) * std::numbers::pi / 180.0) +
        2.0 * pieces(s.radius);
  }
  for (const auto& h : s.holes) n += circle(h.radius);
  return n;
}

namespace {

constexpr double kTriangle = 0.433;  // area of an equilateral triangle of unit side

/// Triangles of a uniform mesh of size `size`: the area over an equilateral triangle's, or, for
/// a shape thinner than the size (a strip with one layer of triangles, which the area counts
/// as a fraction of one), the B − 2 triangles of a triangulation whose B vertices all lie on
/// the boundary.
double uniform_elements(const ShapeSpec& s, double area, double size) {
  return std::max(area / (kTriangle * size * size), boundary_segments(s, size) - 2.0);
}

}  // namespace

double estimate_elements(const BodySpec& b) {
  const double area = shape_area(b.shape), h = b.mesh_size;
  if (!(area > 0) || !(h > 0)) return 0.0;
  double n = uniform_elements(b.shape, area, h);
  for (const auto& r : b.refine) {
    if (!(r.size < h)) continue;
    const double s = r.size, g = std::max(r.growth, 1.0 + 1e-3);
    const double length = r.segment ? (r.p1 - r.p0).norm() : 0.0;
    // Core: a disc of the radius (a strip along a segment) at size s.
    const double core = std::min(area, std::numbers::pi * r.radius * r.radius + 2.0 * r.radius * length);
    n += core / (kTriangle * s * s);
    // Graded zone: at distance t beyond the core the size is about s + (g − 1) t, up to h.
    const double slope = g - 1.0;
    n += (2.0 * length / (kTriangle * slope)) * (1.0 / s - 1.0 / h);
    n += (2.0 * std::numbers::pi / (kTriangle * slope * slope)) *
         (std::log(h / s) + r.radius * slope * (1.0 / s - 1.0 / h));
  }
  double smallest = h;
  for (const auto& r : b.refine) smallest = std::min(smallest, r.size);
  return std::min(n, uniform_elements(b.shape, area, smallest));
}

double default_max_elements() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  const double memory = pages > 0 && page > 0 ? static_cast<double>(pages) * page : 0.0;
  return memory > 0 ? std::min(20e6, std::floor(memory / kBytesPerElement)) : 20e6;
}

}  // namespace c2d::core
