// The parsers of a scene's sections, each from its TOML table to its spec with located errors.
#include "core/scene_sections.hpp"

#include <cmath>
#include <filesystem>

#include "core/errors.hpp"
#include "core/mesh_budget.hpp"
#include "core/mesher.hpp"
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

/// Loads and prescribed displacements: finite (the reader's) and at most 1e30 in size, where E
/// is bounded too: beyond, K u or the load vector overflows.
double bounded(const TomlView& v) {
  const double x = v.number();
  if (!(std::abs(x) <= 1e30)) v.fail("a value of at most 1e30 in magnitude");
  return x;
}

Vec2 bounded_vec2(const TomlView& v) {
  const Vec2 x = v.vec2();
  if (!(x.cwiseAbs().maxCoeff() <= 1e30)) v.fail("components of at most 1e30 in magnitude");
  return x;
}

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

}  // namespace

ShapeSpec parse_shape(const TomlView& v) {
  v.require_table();
  ShapeSpec s;
  s.type = v["type"].choice({"rectangle", "polygon", "disk", "disk_segment", "points"});
  if (s.type == "rectangle") {
    v.check_keys({"type", "min", "max"});
    s.min = shape_point(v["min"]);
    s.max = shape_point(v["max"]);
    if (!(s.max.array() > s.min.array()).all())
      v["max"].fail("max > min in both coordinates");
  } else if (s.type == "polygon") {
    v.check_keys({"type", "points"});
    s.points = bounded_points(v["points"]);
    if (s.points.size() < 3) v["points"].fail("at least 3 points");
    if (const std::string why = polygon_problem(s.points); !why.empty())
      v["points"].fail("a simple polygon of positive area (" + why + ")");
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
    else
      v.check_keys({"type", "center", "radius", "from_deg", "to_deg"});
    s.center = shape_point(v["center"]);
    s.radius = v["radius"].positive();
    if (!(s.radius <= kMaxCoordinate)) v["radius"].fail("a radius of at most 1e15");
    if (s.type == "disk_segment") {
      s.from_deg = v["from_deg"].number();
      s.to_deg = v["to_deg"].number();
      if (!(s.to_deg > s.from_deg) || s.to_deg - s.from_deg > 360.0)
        v["to_deg"].fail("to_deg in (from_deg, from_deg + 360]");
    }
  }
  if (const auto defect = shape_defect(s)) v[defect->key].fail_message(defect->message);
  return s;
}

void parse_analysis(const TomlView& v, AnalysisSpec& a) {
  if (!v.exists()) return;
  v.require_table();
  v.check_keys({"kind", "element", "geometric_nonlinearity", "steps", "smoothing", "target_error",
                "solver", "mesh_scale", "max_newton_iterations", "max_elements"});
  a.state = v["kind"].choice_or({"plane_stress", "plane_strain"}, "plane_stress") == "plane_strain"
                ? PlaneState::kPlaneStrain
                : PlaneState::kPlaneStress;
  a.order = v["element"].choice_or({"T3", "T6"}, "T3") == "T6" ? 2 : 1;
  a.geometric_nonlinearity = v["geometric_nonlinearity"].boolean_or(false);
  if (v.has("steps")) {
    a.steps = v["steps"].integer();
    if (a.steps < 1) v["steps"].fail("an integer >= 1");
  }
  const std::string sm = v["smoothing"].choice_or({"average", "area_average", "l2"}, "l2");
  a.smoothing = sm == "average"        ? Smoothing::kDirectAverage
                : sm == "area_average" ? Smoothing::kAreaAverage
                                       : Smoothing::kGlobalL2;
  a.target_error = v["target_error"].number_or(0.05);
  if (!(a.target_error > 0 && a.target_error < 1))
    v["target_error"].fail("a relative error in (0, 1), e.g. 0.05");
  a.solver = v["solver"].choice_or({"cholmod", "ldlt"}, "cholmod");
  if (v.has("mesh_scale")) a.mesh_scale = v["mesh_scale"].positive();
  if (v.has("max_elements")) {
    a.max_elements = v["max_elements"].number();
    if (!(a.max_elements >= 1)) v["max_elements"].fail("a count >= 1");
  }
  if (v.has("max_newton_iterations")) {
    a.max_newton_iterations = v["max_newton_iterations"].integer();
    if (a.max_newton_iterations < 1) v["max_newton_iterations"].fail("an integer >= 1");
  }
}

void parse_adapt(const TomlView& v, AdaptSpec& a) {
  if (!v.exists()) return;
  v.require_table();
  v.check_keys({"enabled", "target", "max_cycles", "max_shrink", "max_growth"});
  a.enabled = v["enabled"].boolean_or(true);
  a.target = v["target"].number_or(a.target);
  if (!(a.target > 0 && a.target < 1)) v["target"].fail("a relative error in (0, 1), e.g. 0.05");
  if (v.has("max_cycles")) {
    a.max_cycles = v["max_cycles"].integer();
    if (a.max_cycles < 1) v["max_cycles"].fail("an integer >= 1");
  }
  a.limits.max_shrink = v["max_shrink"].number_or(a.limits.max_shrink);
  if (!(a.limits.max_shrink > 0 && a.limits.max_shrink < 1))
    v["max_shrink"].fail("a factor in (0, 1): the smallest h_new / h per cycle");
  a.limits.max_growth = v["max_growth"].number_or(a.limits.max_growth);
  if (!(a.limits.max_growth >= 1)) v["max_growth"].fail("a factor >= 1: the largest h_new / h per cycle");
}

ProbeSpec parse_probe(const TomlView& v) {
  v.check_keys({"name", "quantity", "at", "on", "reduce", "plate"});
  ProbeSpec p;
  p.at.where = v.where();
  p.name = v["name"].string();
  p.quantity = v["quantity"].choice({"ux", "uy", "umag", "sx", "sy", "sxy", "vm", "s1", "s2",
                                     "reaction_x", "reaction_y", "contact_pressure_max",
                                     "contact_length", "contact_force", "contact_penetration",
                                     "contact_tangential_force", "contact_stick_nodes",
                                     "contact_slip_nodes",
                                     "plate_ux", "plate_uy", "plate_rotation", "plate_fx",
                                     "plate_fy", "plate_moment"});
  if (p.quantity.rfind("plate_", 0) == 0) {
    if (v.has("at") || v.has("on") || v.has("reduce"))
      v.fail_message("a plate probe names its plate: give 'plate = NAME' and no 'at', 'on' or 'reduce'");
    p.plate = v["plate"].string();
    return p;
  }
  if (v.has("plate")) v["plate"].fail_message("'plate' belongs to the plate_* quantities only");
  if (p.quantity.rfind("contact_", 0) == 0) {
    if (v.has("at") || v.has("on") || v.has("reduce"))
      v.fail_message("a contact probe is a global quantity: give no 'at', 'on' or 'reduce'");
    return p;
  }
  if (v.has("at") == v.has("on")) v.fail("exactly one of 'at = [x, y]' or 'on = { ... }'");
  if (v.has("at")) p.point = v["at"].vec2();
  if (v.has("on")) p.on = parse_selection(v["on"]);
  const bool reaction = p.quantity.rfind("reaction", 0) == 0;
  if (reaction && p.point) v["at"].fail("a selection 'on = { ... }' for a reaction probe");
  const std::string fallback = p.point ? "value" : (reaction ? "sum" : "maxabs");
  p.reduce = v["reduce"].choice_or({"value", "max", "min", "maxabs", "sum", "mean"}, fallback);
  if (p.on && p.reduce == "value" && p.on->kind != SelectionSpec::Kind::kNearest)
    v["reduce"].fail("max | min | maxabs | sum | mean for a probe over a selection");
  return p;
}

MaterialSpec parse_material(const TomlView& m, const std::vector<MaterialSpec>& earlier) {
  m.check_keys({"name", "E", "nu", "thickness"});
  MaterialSpec ms;
  ms.at.where = m.where();
  ms.name = m["name"].string();
  ms.young = m["E"].positive();
  // Element stiffness ~ E t, displacements ~ load / (E t): beyond these bounds one of them
  // overflows or underflows double precision in any unit system a scene can mean.
  if (!(ms.young >= 1e-30 && ms.young <= 1e30))
    m["E"].fail("a Young's modulus in [1e-30, 1e30] (a stiffer or softer material overflows "
                "double precision in the assembled stiffness or the displacements)");
  ms.poisson = m["nu"].number();
  if (!(ms.poisson > -1.0 && ms.poisson < 0.5)) m["nu"].fail("a Poisson ratio in (-1, 0.5)");
  ms.thickness = m.has("thickness") ? m["thickness"].positive() : 1.0;
  if (!(ms.thickness >= 1e-30 && ms.thickness <= 1e30))
    m["thickness"].fail("a thickness in [1e-30, 1e30]");
  for (const auto& other : earlier)
    if (other.name == ms.name) m["name"].fail("a unique material name");
  return ms;
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

double spring_stiffness_limit(const std::vector<MaterialSpec>& materials) {
  double stiffest = 0.0;
  for (const MaterialSpec& m : materials) stiffest = std::max(stiffest, m.young * m.thickness);
  return std::min(1e12 * stiffest, 1e30);
}

SpringSpec parse_spring(const TomlView& s, int index, const std::vector<MaterialSpec>& materials) {
  s.check_keys({"name", "on", "between", "k"});
  // k = 1e30 on E = 1000 (indeed from 1e18 on) left pivots of 1e-28 of the largest: the run
  // ended "singular ... missing supports?" on a supported body.
  const double limit = spring_stiffness_limit(materials);
  const std::string bound =
      "at most " + number_text(limit) + " (1e12 x E t of the stiffest material: a stiffer "
      "spring is a support in all but name and leaves the stiffness numerically singular; use a "
      "[[support]])";
  SpringSpec sp;
  sp.at.where = s.where();
  sp.name = s["name"].string_or("spring" + std::to_string(index + 1));
  if (s.has("on") == s.has("between"))
    s.fail("either 'on' (springs to ground) or 'between = [selection, selection]'");
  if (s.has("on")) {
    sp.to_ground = true;
    sp.on = parse_selection(s["on"]);
    sp.k_ground = s["k"].vec2();
    if (!sp.k_ground.allFinite() || sp.k_ground.minCoeff() < 0 || sp.k_ground.maxCoeff() <= 0)
      s["k"].fail("[kx, ky], finite, >= 0 and not both 0");
    if (sp.k_ground.maxCoeff() > limit)
      s["k"].fail_message("expected [kx, ky] of " + bound + ", found " +
                          number_text(sp.k_ground.maxCoeff()));
    return sp;
  }
  sp.to_ground = false;
  const std::vector<TomlView> ends = s["between"].items();
  if (ends.size() != 2) s["between"].fail("two selections [ { ... }, { ... } ], one node each");
  sp.a = parse_selection(ends[0]);
  sp.b = parse_selection(ends[1]);
  sp.k = s["k"].positive();
  if (sp.k > limit) s["k"].fail("a stiffness of " + bound);
  return sp;
}

SupportSpec parse_support(const TomlView& s) {
  s.check_keys({"on", "fix", "ux", "uy", "rotate"});
  SupportSpec ss;
  ss.at.where = s.where();
  ss.on = parse_selection(s["on"]);
  for (const auto& item : s["fix"].items()) {
    const std::string c = item.choice({"ux", "uy"});
    (c == "ux" ? ss.ux : ss.uy) = 0.0;
  }
  if (s.has("ux")) {
    if (ss.ux) s["ux"].fail_message("ux is both fixed and prescribed");
    ss.ux = bounded(s["ux"]);
  }
  if (s.has("uy")) {
    if (ss.uy) s["uy"].fail_message("uy is both fixed and prescribed");
    ss.uy = bounded(s["uy"]);
  }
  if (s.has("rotate")) {
    if (ss.ux || ss.uy)
      s["rotate"].fail_message("a rotated support cannot also fix or prescribe ux/uy");
    const TomlView r = s["rotate"];
    r.check_keys({"center", "angle_deg"});
    RotationSpec rot;
    rot.center = r["center"].vec2();
    rot.angle = r["angle_deg"].number() * M_PI / 180.0;
    ss.rotate = rot;
    ss.ux = ss.uy = 0.0;  // both components prescribed (values from the rotation)
  }
  if (!ss.ux && !ss.uy)
    s.fail("'fix = [\"ux\", \"uy\"]', a prescribed 'ux'/'uy' or 'rotate = { center, angle_deg }'");
  return ss;
}

LoadSpec parse_load(const TomlView& l, int index) {
  l.check_keys({"name", "on", "force", "total_force", "traction", "pressure", "body_force",
                "follower", "amplitude"});
  LoadSpec ls;
  ls.name = l["name"].string_or("load" + std::to_string(index + 1));
  ls.at.where = l.where();
  ls.on = parse_selection(l["on"]);
  int kinds = 0;
  if (l.has("force")) ls.kind = LoadSpec::Kind::kNodalForce, ls.vector = bounded_vec2(l["force"]), ++kinds;
  if (l.has("total_force"))
    ls.kind = LoadSpec::Kind::kTotalForce, ls.vector = bounded_vec2(l["total_force"]), ++kinds;
  if (l.has("traction"))
    ls.kind = LoadSpec::Kind::kTraction, ls.vector = bounded_vec2(l["traction"]), ++kinds;
  if (l.has("pressure"))
    ls.kind = LoadSpec::Kind::kPressure, ls.value = bounded(l["pressure"]), ++kinds;
  if (l.has("body_force"))
    ls.kind = LoadSpec::Kind::kBodyForce, ls.vector = bounded_vec2(l["body_force"]), ++kinds;
  if (kinds != 1)
    l.fail("exactly one of force, total_force, traction, pressure, body_force (found " +
           std::to_string(kinds) + ")");
  ls.follower = l["follower"].boolean_or(false);
  if (ls.follower && ls.kind != LoadSpec::Kind::kPressure)
    l["follower"].fail_message("follower = true applies to a pressure only");
  if (l.has("amplitude")) {
    const TomlView a = l["amplitude"];
    const std::vector<Vec2> points = a.points();
    if (points.size() < 2 || points.front().x() != 0.0 || points.back().x() != 1.0)
      a.fail("[[lambda, a], ...] points from lambda = 0 to lambda = 1");
    for (size_t k = 1; k < points.size(); ++k)
      if (!(points[k].x() > points[k - 1].x()))
        a.fail("load factors increasing strictly from 0 to 1");
    for (const Vec2& p : points) {
      if (!std::isfinite(p.y()) || std::abs(p.y()) > 1e6)
        a.fail("finite amplitudes of at most 1e6 in size");
      ls.amplitude.emplace_back(p.x(), p.y());
    }
    if (ls.follower) a.fail_message("an amplitude applies to dead loads only (not follower = true)");
  }
  return ls;
}

void parse_reference(const TomlView& root, Scene& scene) {
  if (root.has("reference")) {
    const TomlView r = root["reference"];
    r.require_table();
    scene.reference_kind = r["kind"].string();
    for (const auto& [key, value] : *r.node()->as_table()) {
      const std::string k(key.str());
      if (k != "kind") scene.reference[k] = r[k].number();
    }
  }
}

}  // namespace c2d::core
