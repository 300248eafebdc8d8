#include "core/model.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <set>

#include "core/elasticity_kernels.hpp"
#include "core/errors.hpp"
#include "core/fill_ordering.hpp"
#include "core/mesher.hpp"
#include "core/rigid_plate.hpp"
#include "core/toml_view.hpp"

namespace c2d::core {

namespace {

// Group and edge names are stored as "body/name"; the scene refers to them by the bare name.
std::string bare_name(const std::string& name) {
  const auto slash = name.find('/');
  return slash == std::string::npos ? name : name.substr(slash + 1);
}

int body_index(const Model& model, const std::string& name) {
  for (size_t i = 0; i < model.body_names.size(); ++i)
    if (model.body_names[i] == name) return static_cast<int>(i);
  return -1;
}

/// The body a selection names (-1 when it names none); throws, with the nearest name, when the
/// named body does not exist.
int selected_body(const Model& model, const SelectionSpec& s) {
  if (s.body.empty()) return -1;
  const int body = body_index(model, s.body);
  if (body < 0)
    throw InputError(s.at.where + ": expected the name of a [[body]], found '" + s.body + "'" +
                     did_you_mean(s.body, model.body_names));
  return body;
}

std::vector<bool> body_nodes(const Model& model, int body) {
  std::vector<bool> in(model.mesh.num_nodes(), body < 0);
  if (body < 0) return in;
  for (int e = 0; e < model.mesh.num_elements(); ++e)
    if (model.mesh.element_body[e] == body)
      for (int i = 0; i < model.mesh.nodes_per_element(); ++i) in[model.mesh.elements[e][i]] = true;
  return in;
}

// Boundary edges named `name` in a body (primitive edge names, physical curves, or the generic
// extremal sides top/bottom/left/right of the body).
std::vector<int> named_edges(const Model& model, const SelectionSpec& s, int body) {
  const Mesh& mesh = model.mesh;
  const std::string prefix = body >= 0 ? model.body_names[body] + "/" : "";
  std::vector<int> out;
  for (const auto& [name, ids] : mesh.edge_groups) {
    if (bare_name(name) != s.name || (body >= 0 && name.rfind(prefix, 0) != 0)) continue;
    out.insert(out.end(), ids.begin(), ids.end());
  }
  if (!out.empty() || (s.name != "top" && s.name != "bottom" && s.name != "left" &&
                       s.name != "right"))
    return out;
  // Generic sides: boundary edges lying on the body's extreme coordinate.
  const int axis = (s.name == "top" || s.name == "bottom") ? 1 : 0;
  const bool upper = s.name == "top" || s.name == "right";
  double extreme = upper ? -1e300 : 1e300;
  for (const auto& be : mesh.boundary_edges)
    if (body < 0 || be.body == body)
      for (int k = 0; k < 2; ++k) {
        const double c = mesh.nodes[be.nodes[k]][axis];
        extreme = upper ? std::max(extreme, c) : std::min(extreme, c);
      }
  const double tol = 1e-9 * model.model_size;
  for (size_t i = 0; i < mesh.boundary_edges.size(); ++i) {
    const auto& be = mesh.boundary_edges[i];
    if (body >= 0 && be.body != body) continue;
    if (std::abs(mesh.nodes[be.nodes[0]][axis] - extreme) <= tol &&
        std::abs(mesh.nodes[be.nodes[1]][axis] - extreme) <= tol)
      out.push_back(static_cast<int>(i));
  }
  return out;
}

/// " (did you mean 'top'?)" for an edge name the body does not have: the nearest of its edge
/// names and the generic sides.
std::string nearest_edge_name(const Model& model, const SelectionSpec& s, int body) {
  const std::string prefix = body >= 0 ? model.body_names[body] + "/" : "";
  std::vector<std::string> names = {"top", "bottom", "left", "right"};
  for (const auto& [name, ids] : model.mesh.edge_groups)
    if (body < 0 || name.rfind(prefix, 0) == 0) names.push_back(bare_name(name));
  return did_you_mean(s.name, names);
}

bool on_predicate(const SelectionSpec& s, const Vec2& p, double tol) {
  using K = SelectionSpec::Kind;
  switch (s.kind) {
    case K::kLine: {
      const Vec2 d = s.p1.normalized();
      const Vec2 r = p - s.p0;
      return std::abs(r.x() * d.y() - r.y() * d.x()) <= tol;
    }
    case K::kSegment: {
      const Vec2 ab = s.p1 - s.p0;
      const double t = std::clamp((p - s.p0).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      return (p - (s.p0 + t * ab)).norm() <= tol;
    }
    case K::kBox:
      return p.x() >= s.p0.x() - tol && p.y() >= s.p0.y() - tol && p.x() <= s.p1.x() + tol &&
             p.y() <= s.p1.y() + tol;
    case K::kArc: {
      const Vec2 r = p - s.p0;
      if (std::abs(r.norm() - s.radius) > tol) return false;
      double ang = std::atan2(r.y(), r.x()) * 180.0 / std::numbers::pi;
      for (double shift : {-360.0, 0.0, 360.0})
        if (ang + shift >= s.from_deg - 1e-9 && ang + shift <= s.to_deg + 1e-9) return true;
      return false;
    }
    default:
      return true;
  }
}

}  // namespace

std::vector<int> select_nodes(const Model& model, const SelectionSpec& s) {
  using K = SelectionSpec::Kind;
  const Mesh& mesh = model.mesh;
  const int body = selected_body(model, s);
  const std::vector<bool> in_body = body_nodes(model, body);
  const double tol = s.tol > 0 ? s.tol : 1e-6 * model.model_size;
  std::vector<int> out;
  switch (s.kind) {
    case K::kNodes:
      for (int n : s.nodes) {
        if (n < 0 || n >= mesh.num_nodes())
          throw InputError(s.at.where + ": expected a node number 1.." +
                           std::to_string(mesh.nodes.size()) + ", found " + std::to_string(n + 1));
        out.push_back(n);
      }
      break;
    case K::kGroup: {
      for (const auto& [name, ids] : mesh.node_groups) {
        if (bare_name(name) == s.name)
          for (int n : ids)
            if (in_body[n]) out.push_back(n);
      }
      break;
    }
    case K::kEdge:
      for (int i : named_edges(model, s, body))
        for (int n : mesh.boundary_edges[i].nodes)
          if (n >= 0) out.push_back(n);
      break;
    case K::kNearest: {
      int best = -1;
      double best_d = 1e300;
      for (int n = 0; n < mesh.num_nodes(); ++n) {
        if (!in_body[n]) continue;
        const double d = (mesh.nodes[n] - s.p0).squaredNorm();
        if (d < best_d) best_d = d, best = n;
      }
      if (best >= 0) out.push_back(best);
      break;
    }
    default:
      for (int n = 0; n < mesh.num_nodes(); ++n)
        if (in_body[n] && on_predicate(s, mesh.nodes[n], tol)) out.push_back(n);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  if (out.empty())
    throw InputError(s.at.where + ": the selection matches no node" +
                     (s.kind == K::kEdge ? " (no boundary edge named '" + s.name + "')" +
                                               nearest_edge_name(model, s, body)
                                         : std::string(" (check coordinates and 'tol')")));
  return out;
}

std::vector<int> select_edges(const Model& model, const SelectionSpec& s) {
  const Mesh& mesh = model.mesh;
  if (s.kind == SelectionSpec::Kind::kEdge) {
    const int body = selected_body(model, s);
    auto out = named_edges(model, s, body);
    if (out.empty())
      throw InputError(s.at.where + ": no boundary edge named '" + s.name + "'" +
                       nearest_edge_name(model, s, body));
    return out;
  }
  const auto nodes = select_nodes(model, s);
  std::vector<bool> in(mesh.num_nodes(), false);
  for (int n : nodes) in[n] = true;
  std::vector<int> out;
  for (size_t i = 0; i < mesh.boundary_edges.size(); ++i) {
    const auto& be = mesh.boundary_edges[i];
    bool all = true;
    for (int n : be.nodes)
      if (n >= 0) all = all && in[n];
    if (all) out.push_back(static_cast<int>(i));
  }
  if (out.empty())
    throw InputError(s.at.where + ": the selection contains no boundary edge (an edge load "
                                  "needs at least two adjacent boundary nodes)");
  return out;
}

namespace {
Vec2 rotated(const Vec2& x, const Vec2& c, double angle) {
  const double co = std::cos(angle), si = std::sin(angle);
  const Vec2 d = x - c;
  return c + Vec2(co * d.x() - si * d.y(), si * d.x() + co * d.y());
}
}  // namespace

VecX prescribed_values(const Model& model, double lambda) {
  VecX u = model.dofs.expand(VecX::Zero(model.dofs.num_free()), lambda);
  if (model.motion_amplitudes.empty()) return u;
  std::vector<double> a(model.motion_amplitudes.size());
  for (size_t k = 0; k < a.size(); ++k) a[k] = model.motion_amplitudes[k].at(lambda);
  for (int dof = 0; dof < static_cast<int>(model.dof_amplitude.size()); ++dof)
    if (const int k = model.dof_amplitude[dof]; k >= 0) u[dof] = a[k] * model.dofs.prescribed(dof);
  return u;
}

VecX prescribed_displacement(const Model& model, double lambda) {
  VecX u = prescribed_values(model, lambda);
  for (const auto& r : model.rotations) {
    const double a = r.amplitude < 0 ? lambda : model.motion_amplitudes[r.amplitude].at(lambda);
    for (int n : r.nodes)
      u.segment<2>(2 * n) =
          rotated(model.mesh.nodes[n], r.center, a * r.angle) - model.mesh.nodes[n];
  }
  return u;
}

VecX prescribed_group(const Model& model, int amplitude) {
  VecX u = model.dofs.expand(VecX::Zero(model.dofs.num_free()), 1.0);
  for (int dof = 0; dof < static_cast<int>(model.dof_amplitude.size()); ++dof)
    if (model.dof_amplitude[dof] != amplitude) u[dof] = 0.0;
  return u;
}

bool has_amplitudes(const Model& model) {
  return !model.amplitude_loads.empty() || !model.motion_amplitudes.empty();
}

int add_motion_amplitude(const AmplitudeTable& table, Model& model) {
  if (table.empty()) return -1;
  model.motion_amplitudes.push_back({table});
  return static_cast<int>(model.motion_amplitudes.size()) - 1;
}

namespace {

/// A scene material as the element kernels' material, in the analysis' plane state.
Material make_material(const MaterialSpec& m, PlaneState state) {
  Material mat;
  mat.name = m.name;
  mat.young = m.young;
  mat.poisson = m.poisson;
  mat.thickness = m.thickness;
  mat.state = state;
  return mat;
}

/// The mesh and materials: a legacy file's explicit mesh, or every body meshed and appended.
void mesh_bodies(const Scene& scene, Model& model) {
  const PlaneState state = scene.analysis.state;
  if (scene.explicit_model) {
    model.mesh = scene.explicit_model->mesh;
    for (const auto& m : scene.explicit_model->materials)
      model.materials.push_back(make_material(m, state));
    model.body_names = {"body"};
    return;
  }
  model.mesh.order = scene.analysis.order;
  for (const auto& m : scene.materials) model.materials.push_back(make_material(m, state));
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    const BodySpec& spec = scene.bodies[b];
    Mesh body_mesh = mesh_body(spec, scene.analysis.order);
    int mat = 0;
    for (size_t m = 0; m < scene.materials.size(); ++m)
      if (scene.materials[m].name == spec.material) mat = static_cast<int>(m);
    model.mesh.append(body_mesh, static_cast<int>(b), mat, spec.name + "/");
    model.body_names.push_back(spec.name);
  }
}

/// Prescribes `value` on `dof` under motion amplitude `amplitude`; false when the DOF already
/// has another value, or the same non-zero value under another amplitude.
bool prescribe_dof(int dof, double value, int amplitude, Model& model) {
  const bool before = model.dofs.is_constrained(dof);
  if (!model.dofs.constrain(dof, value)) return false;
  // A value prescribed twice must also grow alike (0 grows alike under any amplitude).
  int& kept = model.dof_amplitude[dof];
  if (before && kept != amplitude && value != 0.0) return false;
  if (!before || value != 0.0) kept = amplitude;
  return true;
}

/// Prescribes the supports' displacements (a rotation's per node) in the DOF map.
void apply_supports(const Scene& scene, Model& model) {
  model.dofs = DofMap(model.mesh.num_dofs() + 3 * static_cast<int>(model.plates.size()));
  model.dof_amplitude.assign(model.dofs.num_dofs(), -1);
  for (const auto& s : scene.supports) {
    const std::vector<int> nodes = select_nodes(model, s.on);
    const int amplitude = add_motion_amplitude(s.amplitude, model);
    if (s.rotate) model.rotations.push_back({nodes, s.rotate->center, s.rotate->angle, amplitude});
    for (int n : nodes) {
      Vec2 turned = Vec2::Zero();
      if (s.rotate)
        turned = rotated(model.mesh.nodes[n], s.rotate->center, s.rotate->angle) - model.mesh.nodes[n];
      for (int c = 0; c < 2; ++c) {
        const auto& v = c == 0 ? s.ux : s.uy;
        if (v && !prescribe_dof(2 * n + c, s.rotate ? turned[c] : *v, amplitude, model))
          throw InputError(s.at.where + ": node " + std::to_string(n + 1) +
                           " already has a different prescribed " + (c == 0 ? "ux" : "uy") +
                           " (or the same value under another amplitude)");
      }
    }
  }
  prescribe_plates(scene, model);
  model.dofs.finalize();
}

/// A body force on the elements whose nodes are all selected.
void add_body_force(const Model& model, const LoadSpec& l, VecX& f) {
  const auto nodes = select_nodes(model, l.on);
  std::vector<bool> in(model.mesh.num_nodes(), false);
  for (int n : nodes) in[n] = true;
  int loaded = 0;
  for (int e = 0; e < model.mesh.num_elements(); ++e) {
    bool all = true;
    for (int i = 0; i < model.mesh.nodes_per_element(); ++i)
      all = all && in[model.mesh.elements[e][i]];
    if (!all) continue;
    ++loaded;
    const LocalVector fe =
        element_body_force(model.mesh.element_coords(e),
                           model.materials[model.mesh.element_material[e]].thickness, l.vector);
    for (int i = 0; i < model.mesh.nodes_per_element(); ++i)
      f.segment<2>(2 * model.mesh.elements[e][i]) += fe.segment<2>(2 * i);
  }
  // (It was ignored without a word: a body force on a node or an edge loads nothing.)
  if (loaded == 0)
    throw InputError(l.on.at.where + ": expected a selection holding whole elements for a "
                     "body_force (a body, or a region), found " + std::to_string(nodes.size()) +
                     " nodes and no whole element");
}

/// A traction, pressure or total force on the selected boundary edges.
void add_edge_load(const Model& model, const LoadSpec& l, VecX& f) {
  using K = LoadSpec::Kind;
  const auto edges = select_edges(model, l.on);
  const int nn = model.mesh.order == 1 ? 2 : 3;
  auto edge_coords = [&](const BoundaryEdge& be) {
    Eigen::MatrixX2d x(nn, 2);
    for (int i = 0; i < nn; ++i) x.row(i) = model.mesh.nodes[be.nodes[i]].transpose();
    return x;
  };
  Vec2 traction = l.vector;
  double pressure = l.kind == K::kPressure ? l.value : 0.0;
  if (l.kind == K::kPressure) traction.setZero();
  if (l.kind == K::kTotalForce) {
    // Uniform traction whose resultant is the given force: F / (Σ t L).
    double tl = 0.0;
    for (int i : edges) {
      const auto& be = model.mesh.boundary_edges[i];
      tl += edge_length(edge_coords(be)) *
            model.materials[model.mesh.element_material[be.element]].thickness;
    }
    traction = l.vector / tl;
  }
  for (int i : edges) {
    const auto& be = model.mesh.boundary_edges[i];
    const double t = model.materials[model.mesh.element_material[be.element]].thickness;
    const Eigen::VectorXd fe = edge_load(edge_coords(be), t, traction, pressure);
    for (int k = 0; k < nn; ++k) f.segment<2>(2 * be.nodes[k]) += fe.segment<2>(2 * k);
  }
}

/// The matrix M of the follower pressures (f = M x, full DOFs) and their reference force M X.
void add_follower_loads(const Scene& scene, Model& model) {
  std::vector<Eigen::Triplet<double>> t;
  const int nn = model.mesh.order == 1 ? 2 : 3;
  for (const auto& l : scene.loads) {
    if (!l.follower) continue;
    if (model.follower_where.empty()) model.follower_where = l.at.where;
    for (int i : select_edges(model, l.on)) {
      const auto& be = model.mesh.boundary_edges[i];
      const double th = model.materials[model.mesh.element_material[be.element]].thickness;
      const Eigen::MatrixXd m = edge_pressure_matrix(nn, th, l.value);
      for (int a = 0; a < 2 * nn; ++a)
        for (int b = 0; b < 2 * nn; ++b)
          if (m(a, b) != 0.0) t.emplace_back(2 * be.nodes[a / 2] + a % 2, 2 * be.nodes[b / 2] + b % 2, m(a, b));
    }
  }
  if (model.follower_where.empty()) return;
  const int n = model.dofs.num_dofs();
  model.follower_matrix = SpMat(n, n);
  model.follower_matrix.setFromTriplets(t.begin(), t.end());
  VecX x = VecX::Zero(n);
  for (int v = 0; v < model.mesh.num_nodes(); ++v) x.segment<2>(2 * v) = model.mesh.nodes[v];
  model.follower_reference = model.follower_matrix * x;
}

/// The external force vector: every load, in the scene's order (a load with an amplitude in
/// its own vector).
void apply_loads(const Scene& scene, Model& model) {
  model.external_force = VecX::Zero(model.dofs.num_dofs());
  add_plate_loads(scene, model);
  for (const auto& l : scene.loads) {
    using K = LoadSpec::Kind;
    if (!l.amplitude.empty())
      model.amplitude_loads.push_back({VecX::Zero(model.dofs.num_dofs()), {l.amplitude}});
    VecX& f = l.amplitude.empty() ? model.external_force : model.amplitude_loads.back().force;
    if (l.kind == K::kNodalForce) {
      for (int n : select_nodes(model, l.on)) f.segment<2>(2 * n) += l.vector;
    } else if (l.kind == K::kBodyForce) {
      add_body_force(model, l, f);
    } else {
      add_edge_load(model, l, f);
    }
  }
}

}  // namespace

namespace {

/// The scene's springs on the model's nodes.
void add_springs(const Scene& scene, Model& model) {
  for (const SpringSpec& sp : scene.springs) {
    if (sp.to_ground) {
      for (int n : select_nodes(model, sp.on)) model.springs.push_back({sp.name, n, -1, sp.k_ground, 0.0});
      continue;
    }
    const std::vector<int> a = select_nodes(model, sp.a), b = select_nodes(model, sp.b);
    if (a.size() != 1 || b.size() != 1)
      throw InputError(sp.at.where + ": between: each selection must select one node, they select " +
                       std::to_string(a.size()) + " and " + std::to_string(b.size()));
    if ((model.mesh.nodes[a[0]] - model.mesh.nodes[b[0]]).norm() <= 1e-12 * model.model_size)
      throw InputError(sp.at.where + ": between: the two nodes coincide (an axial spring needs a "
                       "length); use a spring to ground or a [[constraint]]");
    model.springs.push_back({sp.name, a[0], b[0], Vec2::Zero(), sp.k});
  }
}

}  // namespace

Model build_model(const Scene& scene) {
  Model model;
  const auto t0 = std::chrono::steady_clock::now();
  mesh_bodies(scene, model);
  model.node_material.assign(model.mesh.num_nodes(), 0);
  for (int e = 0; e < model.mesh.num_elements(); ++e)
    for (int i = 0; i < model.mesh.nodes_per_element(); ++i)
      model.node_material[model.mesh.elements[e][i]] = model.mesh.element_material[e];
  model.mesh_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const Eigen::Vector4d box = model.mesh.bounding_box();
  model.model_size = std::hypot(box[2] - box[0], box[3] - box[1]);

  add_plates(scene, model);
  apply_supports(scene, model);
  apply_loads(scene, model);
  add_follower_loads(scene, model);
  add_springs(scene, model);
  model.fill_order = std::make_shared<const FillOrder>(mesh_fill_order(model.mesh, model.dofs));
  return model;
}

double Amplitude::peak() const {
  double largest = 0.0;
  for (const auto& [lambda, value] : table) largest = std::max(largest, std::abs(value));
  return largest;
}

double Amplitude::at(double lambda) const {
  if (lambda <= table.front().first) return table.front().second;
  for (size_t k = 1; k < table.size(); ++k)
    if (lambda <= table[k].first) {
      const auto& [l0, a0] = table[k - 1];
      const auto& [l1, a1] = table[k];
      return a0 + (a1 - a0) * (lambda - l0) / (l1 - l0);
    }
  return table.back().second;
}

VecX Model::external_force_at(double lambda) const {
  VecX f = lambda * external_force;
  for (const AmplitudeLoad& a : amplitude_loads) f += a.at(lambda) * a.force;
  return f;
}

}  // namespace c2d::core
