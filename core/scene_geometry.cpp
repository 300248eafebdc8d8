// The parsers of a scene's geometric sections: where things are (selections, refinement
// rules, shapes, bodies with their meshes), each from its TOML table to its spec with located
// errors. The sections of what acts on them are in scene_sections.cpp.
#include <cmath>
#include <filesystem>
#include <numbers>

#include "core/errors.hpp"
#include "core/mesh_budget.hpp"
#include "core/scene_sections.hpp"
#include "core/shape_check.hpp"

namespace c2d::core {

SelectionSpec parse_selection(const TomlView& v) {
  v.require_table();
  v.check_keys({"body", "group", "edge", "line", "segment", "box", "arc", "nearest", "nodes",
                "tol"});
  SelectionSpec s;
  s.at.where = v.where();
  s.body = v["body"].string_or("");
  s.tol = v.has("tol") ? v["tol"].positive() : -1.0;
  int kinds = 0;
  if (v.has("group")) {
    s.kind = SelectionSpec::Kind::kGroup;
    s.name = v["group"].string();
    ++kinds;
  }
  if (v.has("edge")) {
    s.kind = SelectionSpec::Kind::kEdge;
    s.name = v["edge"].string();
    ++kinds;
  }
  if (v.has("line")) {
    const TomlView l = v["line"];
    l.require_table();
    l.check_keys({"point", "direction"});
    s.kind = SelectionSpec::Kind::kLine;
    s.p0 = l["point"].vec2();
    s.p1 = l["direction"].vec2();
    if (s.p1.norm() == 0.0) l["direction"].fail("a non-zero direction");
    ++kinds;
  }
  if (v.has("segment")) {
    const auto pts = v["segment"].points();
    if (pts.size() != 2) v["segment"].fail("two points [[x0, y0], [x1, y1]]");
    s.kind = SelectionSpec::Kind::kSegment;
    s.p0 = pts[0];
    s.p1 = pts[1];
    ++kinds;
  }
  if (v.has("box")) {
    const auto pts = v["box"].points();
    if (pts.size() != 2) v["box"].fail("two corners [[xmin, ymin], [xmax, ymax]]");
    s.kind = SelectionSpec::Kind::kBox;
    s.p0 = pts[0].cwiseMin(pts[1]);
    s.p1 = pts[0].cwiseMax(pts[1]);
    ++kinds;
  }
  if (v.has("arc")) {
    const TomlView a = v["arc"];
    a.require_table();
    a.check_keys({"center", "radius", "from_deg", "to_deg"});
    s.kind = SelectionSpec::Kind::kArc;
    s.p0 = a["center"].vec2();
    s.radius = a["radius"].positive();
    s.from_deg = a["from_deg"].number_or(-1e9);
    s.to_deg = a["to_deg"].number_or(1e9);
    ++kinds;
  }
  if (v.has("nearest")) {
    s.kind = SelectionSpec::Kind::kNearest;
    s.p0 = v["nearest"].vec2();
    ++kinds;
  }
  if (v.has("nodes")) {
    s.kind = SelectionSpec::Kind::kNodes;
    for (const auto& item : v["nodes"].items()) {
      const int id = item.integer();
      if (id < 1) item.fail("a node number >= 1");
      s.nodes.push_back(id - 1);
    }
    ++kinds;
  }
  if (kinds > 1)
    v.fail_message("give one predicate (group, edge, line, segment, box, arc, nearest or nodes), "
                   "found " + std::to_string(kinds));
  if (kinds == 0 && s.body.empty())
    v.fail("a predicate: body, group, edge, line, segment, box, arc, nearest or nodes");
  return s;
}

RefineSpec parse_refine(const TomlView& v) {
  v.require_table();
  v.check_keys({"near", "near_segment", "size", "radius", "growth"});
  RefineSpec r;
  if (v.has("near") == v.has("near_segment")) v.fail("exactly one of 'near' or 'near_segment'");
  if (v.has("near")) {
    r.p0 = v["near"].vec2();
  } else {
    const auto pts = v["near_segment"].points();
    if (pts.size() != 2) v["near_segment"].fail("two points [[x0, y0], [x1, y1]]");
    r.segment = true;
    r.p0 = pts[0];
    r.p1 = pts[1];
  }
  r.size = v["size"].positive();
  r.radius = v.has("radius") ? v["radius"].number() : 0.0;
  if (r.radius < 0) v["radius"].fail("a radius >= 0");
  r.growth = v["growth"].number_or(1.2);
  if (r.growth < 1.0 || r.growth > 10.0) v["growth"].fail("a growth rate in [1, 10]");
  return r;
}
namespace {

/// Shape coordinates and radii: at most 1e15 in size. gmsh's geometry fails beyond about 1e16
/// (a rectangle of 1e17 aborted the program inside gmsh, one of 1e20 meshed without end).
constexpr double kMaxCoordinate = 1e15;

Vec2 shape_point(const TomlView& v) {
  const Vec2 x = v.vec2();
  if (!(x.cwiseAbs().maxCoeff() <= kMaxCoordinate))
    v.fail("coordinates of at most 1e15 in magnitude (gmsh's geometry fails beyond about 1e16)");
  return x;
}

std::vector<Vec2> bounded_points(const TomlView& v) {
  std::vector<Vec2> pts = v.points();
  for (const auto& item : v.items()) shape_point(item);
  return pts;
}

/// A polygon's `arcs = [{ edge = k, center = [x, y] }, ...]`: each edge at most once, its ends
/// equidistant from the centre (to 1e-9 of the radius), the arc between them under 180 degrees
/// (gmsh's circle arcs; a longer one is two edges).
std::vector<ShapeSpec::Arc> parse_arcs(const TomlView& v, const std::vector<Vec2>& points) {
  std::vector<ShapeSpec::Arc> arcs;
  const int n = static_cast<int>(points.size());
  for (const TomlView& a : v.tables()) {
    a.check_keys({"edge", "center"});
    ShapeSpec::Arc arc;
    arc.edge = a["edge"].integer();
    if (arc.edge < 0 || arc.edge >= n)
      a["edge"].fail("an edge index from 0 to " + std::to_string(n - 1) +
                     " (edge k joins points[k] and points[k + 1])");
    for (const ShapeSpec::Arc& other : arcs)
      if (other.edge == arc.edge) a["edge"].fail("each edge at most once");
    arc.center = shape_point(a["center"]);
    const Vec2 from = points[arc.edge] - arc.center, to = points[(arc.edge + 1) % n] - arc.center;
    arc.radius = from.norm();
    if (!(std::abs(to.norm() - arc.radius) <= 1e-9 * arc.radius))
      a["center"].fail("a centre equidistant from the edge's ends (found " +
                       number_text(from.norm()) + " and " + number_text(to.norm()) + ")");
    const double angle = angle_between(from, to);
    if (!(angle < std::numbers::pi * (1.0 - 1e-9)))
      a["center"].fail(
          "an arc of less than 180 degrees (split a longer one at a point of its "
          "circle), found 180");
    arcs.push_back(arc);
  }
  return arcs;
}

}  // namespace

ShapeSpec parse_shape(const TomlView& v) {
  v.require_table();
  ShapeSpec s;
  s.type = v["type"].choice({"rectangle", "polygon", "disk", "disk_segment", "annulus", "points"});
  if (s.type == "rectangle") {
    v.check_keys({"type", "min", "max", "holes"});
    s.min = shape_point(v["min"]);
    s.max = shape_point(v["max"]);
    if (!(s.max.array() > s.min.array()).all())
      v["max"].fail("max > min in both coordinates");
  } else if (s.type == "polygon") {
    v.check_keys({"type", "points", "holes", "arcs"});
    s.points = bounded_points(v["points"]);
    if (s.points.size() < 3) v["points"].fail("at least 3 points");
    if (const std::string why = polygon_problem(s.points); !why.empty())
      v["points"].fail("a simple polygon of positive area (" + why + ")");
    if (v.has("arcs")) s.arcs = parse_arcs(v["arcs"], s.points);
  } else if (s.type == "points") {
    // A point cloud triangulated as it is (Delaunay): the seed's pre-processor. The checks of
    // the cloud itself (duplicates, collinear, outside the boundary) are the mesher's.
    v.check_keys({"type", "points", "boundary"});
    s.points = bounded_points(v["points"]);
    if (s.points.size() < 3) v["points"].fail("at least 3 points");
    if (v.has("boundary")) {
      s.boundary = bounded_points(v["boundary"]);
      if (s.boundary.size() < 3) v["boundary"].fail("a polygon of at least 3 points");
      if (const std::string why = polygon_problem(s.boundary); !why.empty())
        v["boundary"].fail("a simple polygon of positive area (" + why + ")");
    }
  } else {
    if (s.type == "disk")
      v.check_keys({"type", "center", "radius"});
    else if (s.type == "annulus")
      v.check_keys({"type", "center", "radius", "inner_radius"});
    else
      v.check_keys({"type", "center", "radius", "from_deg", "to_deg"});
    s.center = shape_point(v["center"]);
    s.radius = v["radius"].positive();
    if (!(s.radius <= kMaxCoordinate)) v["radius"].fail("a radius of at most 1e15");
    if (s.type == "annulus") {
      s.inner_radius = v["inner_radius"].positive();
      if (!(s.inner_radius < s.radius)) v["inner_radius"].fail("inner_radius < radius");
    }
    if (s.type == "disk_segment") {
      s.from_deg = v["from_deg"].number();
      s.to_deg = v["to_deg"].number();
      if (!(s.to_deg > s.from_deg) || s.to_deg - s.from_deg > 360.0)
        v["to_deg"].fail("to_deg in (from_deg, from_deg + 360]");
    }
  }
  if (v.has("holes")) {
    for (const TomlView& h : v["holes"].tables()) {
      h.check_keys({"center", "radius"});
      ShapeSpec::Hole hole;
      hole.center = shape_point(h["center"]);
      hole.radius = h["radius"].positive();
      s.holes.push_back(hole);
    }
  }
  if (const auto defect = shape_defect(s)) v[defect->key].fail_message(defect->message);
  return s;
}

namespace {

/// Sizes gmsh can resolve (at least 1e-7 of the body's diagonal, after mesh_scale) and an
/// element count within analysis.max_elements, both refused at the body's mesh table.
void check_mesh_budget(const TomlView& mesh, const AnalysisSpec& analysis, const BodySpec& bs) {
  const double diagonal = shape_diagonal(bs.shape);
  auto resolvable = [&](double size, const TomlView& at) {
    if (bs.mesh_size > 0 && !(size >= 1e-7 * diagonal))
      at.fail("a size of at least 1e-7 of the body's extent " + number_text(diagonal) +
              " (after analysis.mesh_scale = " + number_text(analysis.mesh_scale) + ": " +
              number_text(size) + ")");
  };
  resolvable(bs.mesh_size, mesh["size"]);
  const auto refine = mesh["refine"].items();
  for (size_t i = 0; i < bs.refine.size(); ++i) resolvable(bs.refine[i].size, refine[i]["size"]);
  const double estimate = estimate_elements(bs);
  const bool given = analysis.max_elements > 0;
  const double limit = given ? analysis.max_elements : default_max_elements();
  if (estimate > limit)
    mesh.fail("a mesh of at most analysis.max_elements = " +
              std::to_string(static_cast<long long>(limit)) +
              (given ? std::string() : std::string(" (the default: what this machine's memory holds)")) +
              " triangles; these sizes (after analysis.mesh_scale = " +
              number_text(analysis.mesh_scale) + ") give about " +
              std::to_string(static_cast<long long>(std::min(estimate, 9e18))));
}

/// The body's mesh: a .msh file (resolved against the scene's folder) or a shape with sizes.
void parse_body_mesh(const TomlView& b, const Scene& scene, BodySpec& bs) {
  const TomlView mesh = b["mesh"];
  const bool cloud = b["shape"].exists() && b["shape"]["type"].exists() &&
                     b["shape"]["type"].string() == "points";
  if (!(cloud && !mesh.exists())) mesh.require_table();
  mesh.check_keys({"size", "refine", "algorithm", "file"});
  if (mesh.has("file")) {
    if (b.has("shape")) b["shape"].fail_message("give either 'shape' or 'mesh.file', not both");
    bs.msh_file = mesh["file"].string();
    const std::filesystem::path rel(bs.msh_file);
    if (rel.is_relative())
      bs.msh_file = (std::filesystem::path(scene.path).parent_path() / rel).lexically_normal().string();
    if (!std::filesystem::exists(bs.msh_file))
      mesh["file"].fail("an existing .msh file (looked for " + bs.msh_file + ")");
    return;
  }
  bs.shape = parse_shape(b["shape"]);
  // A point cloud is meshed as given: no size (mesh_size stays 0).
  if (!cloud) bs.mesh_size = mesh["size"].positive() * scene.analysis.mesh_scale;
  for (const auto& r : mesh["refine"].items()) {
    bs.refine.push_back(parse_refine(r));
    // The rule's whole size field, size + (growth − 1)·max(0, d − radius), scales: scaling only
    // `size` would leave the graded zone (d > radius) as coarse as before, and refinement levels
    // would stall on the error of that zone (hertz_rigid_fast's pressure profile at mesh_scale
    // 1, 1/2, 1/4, 1/8: 0.45, 0.45, 0.27, 0.30 %; with the slope scaled 0.45, 0.21, 0.19, 0.09 %).
    bs.refine.back().size *= scene.analysis.mesh_scale;
    bs.refine.back().growth = 1.0 + (bs.refine.back().growth - 1.0) * scene.analysis.mesh_scale;
  }
  bs.algorithm = mesh["algorithm"].choice_or({"frontal", "delaunay"}, "frontal");
  check_mesh_budget(mesh, scene.analysis, bs);
}

}  // namespace

BodySpec parse_body(const TomlView& b, const Scene& scene) {
  b.check_keys({"name", "material", "shape", "mesh"});
  BodySpec bs;
  bs.at.where = b.where();
  bs.name = b["name"].string();
  for (const auto& other : scene.bodies)
    if (other.name == bs.name) b["name"].fail("a unique body name");
  bs.material = b["material"].string();
  bool known = false;
  std::vector<std::string> names;
  for (const auto& m : scene.materials) {
    known |= m.name == bs.material;
    names.push_back(m.name);
  }
  if (!known) b["material"].fail("the name of a [[material]]" + did_you_mean(bs.material, names));
  parse_body_mesh(b, scene, bs);
  return bs;
}

}  // namespace c2d::core
