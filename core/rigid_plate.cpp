#include "core/rigid_plate.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "core/errors.hpp"
#include "core/scene_sections.hpp"

namespace c2d::core {

PlateSpec parse_plate(const TomlView& v, int index) {
  v.check_keys({"name", "on", "reference", "attach", "force", "moment", "ux", "uy", "rotation_deg",
                "fix", "amplitude"});
  PlateSpec p;
  p.at.where = v.where();
  p.name = v["name"].string_or("plate" + std::to_string(index + 1));
  p.on = parse_selection(v["on"]);
  if (v.has("reference")) p.reference = v["reference"].vec2();
  p.normal_only = v["attach"].choice_or({"all", "normal"}, "all") == "normal";
  if (v.has("force")) p.force = v["force"].vec2();
  if (!(p.force.cwiseAbs().maxCoeff() <= 1e30)) v["force"].fail("components of at most 1e30 in magnitude");
  p.moment = v["moment"].number_or(0.0);
  if (!(std::abs(p.moment) <= 1e30)) v["moment"].fail("a value of at most 1e30 in magnitude");
  for (const auto& item : v["fix"].items()) {
    const std::string c = item.choice({"ux", "uy", "rotation"});
    (c == "ux" ? p.ux : c == "uy" ? p.uy : p.rotation) = 0.0;
  }
  auto prescribed = [&](const char* key, std::optional<double>& value, double scale) {
    if (!v.has(key)) return;
    if (value) v[key].fail_message(std::string(key) + " is both fixed and prescribed");
    value = v[key].number() * scale;
    if (!(std::abs(*value) <= 1e30)) v[key].fail("a value of at most 1e30 in magnitude");
  };
  prescribed("ux", p.ux, 1.0);
  prescribed("uy", p.uy, 1.0);
  prescribed("rotation_deg", p.rotation, std::numbers::pi / 180.0);
  if (p.ux && p.force.x() != 0.0) v["force"].fail_message("force x on a prescribed ux: give one");
  if (p.uy && p.force.y() != 0.0) v["force"].fail_message("force y on a prescribed uy: give one");
  if (p.rotation && p.moment != 0.0)
    v["moment"].fail_message("a moment on a prescribed rotation: give one");
  if (v.has("amplitude")) p.amplitude = parse_amplitude(v["amplitude"]);
  return p;
}

namespace {

/// Unit outward normal of a boundary edge: (t_y, −t_x), its element being on the left.
Vec2 outward_normal(const Mesh& mesh, const BoundaryEdge& be) {
  const Vec2 t = mesh.nodes[be.nodes[1]] - mesh.nodes[be.nodes[0]];
  return Vec2(t.y(), -t.x()).normalized();
}

RigidPlate make_plate(const PlateSpec& spec, const Model& model, int dof) {
  const Mesh& mesh = model.mesh;
  RigidPlate plate;
  plate.name = spec.name;
  plate.dof = dof;
  plate.where = spec.at.where;
  plate.normal_only = spec.normal_only;
  const std::vector<int> edges = select_edges(model, spec.on);
  if (edges.empty())
    throw InputError(spec.at.where + ": on: expected boundary edges to attach the plate to, the "
                     "selection holds none (select an edge or a line along one)");
  for (int e : edges)
    for (int n : mesh.boundary_edges[e].nodes)
      if (n >= 0) plate.nodes.push_back(n);
  std::sort(plate.nodes.begin(), plate.nodes.end());
  plate.nodes.erase(std::unique(plate.nodes.begin(), plate.nodes.end()), plate.nodes.end());
  Vec2 centroid = Vec2::Zero();
  for (int n : plate.nodes) centroid += mesh.nodes[n];
  plate.reference = spec.reference ? *spec.reference : Vec2(centroid / plate.nodes.size());
  if (!spec.normal_only) return plate;
  // Frictionless attachment: the edge slides along the plate, so it must be straight.
  plate.normal = outward_normal(mesh, mesh.boundary_edges[edges[0]]);
  const double tol = 1e-9 * model.model_size;
  const Vec2 origin = mesh.nodes[plate.nodes[0]];
  for (int e : edges) {
    const Vec2 n = outward_normal(mesh, mesh.boundary_edges[e]);
    bool straight = n.dot(plate.normal) > 1.0 - 1e-9;
    for (int node : mesh.boundary_edges[e].nodes)
      straight = straight && (node < 0 || std::abs(plate.normal.dot(mesh.nodes[node] - origin)) <= tol);
    if (!straight)
      throw InputError(spec.at.where + ": attach = \"normal\": expected a straight edge (the plate "
                       "slides along it), found edges that turn (use attach = \"all\")");
  }
  // Nothing holds the plate along its edge but a prescribed component along it.
  const Vec2 t(-plate.normal.y(), plate.normal.x());
  if (!(spec.ux && std::abs(t.x()) > 1e-9) && !(spec.uy && std::abs(t.y()) > 1e-9))
    throw InputError(spec.at.where + ": attach = \"normal\": the plate is free to slide along its "
                     "edge; expected ux or uy prescribed (or fixed) along it");
  return plate;
}

}  // namespace

void add_plates(const Scene& scene, Model& model) {
  int dof = model.mesh.num_dofs();
  for (const PlateSpec& spec : scene.plates) {
    model.plates.push_back(make_plate(spec, model, dof));
    dof += 3;
  }
}

void prescribe_plates(const Scene& scene, Model& model) {
  for (size_t p = 0; p < scene.plates.size(); ++p) {
    const PlateSpec& spec = scene.plates[p];
    const int dof = model.plates[p].dof;
    const bool moved = spec.ux || spec.uy || spec.rotation;
    const int amplitude = moved ? add_motion_amplitude(spec.amplitude, model) : -1;
    const std::optional<double> values[3] = {spec.ux, spec.uy, spec.rotation};
    // The plate's own DOFs: no support prescribes them, so no value or amplitude conflicts.
    for (int c = 0; c < 3; ++c)
      if (values[c]) {
        model.dofs.constrain(dof + c, *values[c]);
        model.dof_amplitude[dof + c] = amplitude;
      }
  }
}

void add_plate_loads(const Scene& scene, Model& model) {
  for (size_t p = 0; p < scene.plates.size(); ++p) {
    const PlateSpec& spec = scene.plates[p];
    if (spec.force.isZero() && spec.moment == 0.0) continue;
    VecX* f = &model.external_force;
    if (!spec.amplitude.empty()) {
      model.amplitude_loads.push_back({VecX::Zero(model.dofs.num_dofs()), {spec.amplitude}});
      f = &model.amplitude_loads.back().force;
    }
    const int dof = model.plates[p].dof;
    f->segment<2>(dof) += spec.force;
    (*f)[dof + 2] += spec.moment;
  }
}

}  // namespace c2d::core
