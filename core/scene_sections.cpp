// The parsers of a scene's sections of what acts (analysis, adaptivity, probes, materials,
// springs, supports, loads, the reference), each from its TOML table to its spec with located
// errors. The geometric sections (selections, refinement, shapes, bodies) are in
// scene_geometry.cpp.
#include "core/scene_sections.hpp"

#include <cmath>

#include "core/errors.hpp"

namespace c2d::core {

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

}  // namespace

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
  s.check_keys({"on", "fix", "ux", "uy", "rotate", "amplitude"});
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
  if (s.has("amplitude")) ss.amplitude = parse_amplitude(s["amplitude"]);
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
    ls.amplitude = parse_amplitude(l["amplitude"]);
    if (ls.follower)
      l["amplitude"].fail_message("an amplitude applies to dead loads only (not follower = true)");
  }
  return ls;
}

AmplitudeTable parse_amplitude(const TomlView& a) {
  const std::vector<Vec2> points = a.points();
  if (points.size() < 2 || points.front().x() != 0.0 || points.back().x() != 1.0)
    a.fail("[[lambda, a], ...] points from lambda = 0 to lambda = 1");
  for (size_t k = 1; k < points.size(); ++k)
    if (!(points[k].x() > points[k - 1].x()))
      a.fail("load factors increasing strictly from 0 to 1");
  AmplitudeTable table;
  for (const Vec2& p : points) {
    if (!std::isfinite(p.y()) || std::abs(p.y()) > 1e6)
      a.fail("finite amplitudes of at most 1e6 in size");
    table.emplace_back(p.x(), p.y());
  }
  return table;
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
