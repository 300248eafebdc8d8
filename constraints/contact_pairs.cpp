#include "constraints/contact_pairs.hpp"

#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <utility>

#include "constraints/discretizations/node_to_node.hpp"
#include "core/errors.hpp"

namespace c2d::constraints {

double chord(const std::vector<Vec2>& x, const MasterEdge& e) {
  return (x[e.nodes[1]] - x[e.nodes[0]]).norm();
}

ContactPairs::ContactPairs(const core::Model& model, const ContactSceneSpec& spec,
                           const core::Scene& scene)
    : model_(model), specs_(spec.pairs), obstacles_(spec.obstacles) {
  const core::Mesh& mesh = model.mesh;
  master_outward_.assign(mesh.num_nodes(), Vec2::Zero());
  for (size_t c = 0; c < specs_.size(); ++c) {
    const ContactPairSpec& cs = specs_[c];
    const DiscretizationInfo* info = find_discretization(cs.detection);
    if (!info) throw InputError(cs.where + ": unknown detection '" + cs.detection + "'");
    add_slave_edges(cs, info->slave_surface);
    add_master_normals(cs);
    pairs_.push_back(info->create({model, cs, obstacles_, static_cast<int>(c)}));
    const DiscretizationInfo* nodal = find_discretization("node_to_segment");
    gauges_.push_back(cs.detection == nodal->name
                          ? nullptr
                          : nodal->create({model, cs, obstacles_, static_cast<int>(c)}));
  }
  for (Vec2& n : master_outward_)
    if (n.squaredNorm() > 0) n.normalize();
  if (scene.explicit_model) add_gap_elements(*scene.explicit_model);
  std::vector<int> slaves;
  for (const auto& p : pairs_) {
    first_slot_.push_back(num_slots_);
    num_slots_ += p->num_slots();
    slaves.insert(slaves.end(), p->slave_nodes().begin(), p->slave_nodes().end());
  }
  std::sort(slaves.begin(), slaves.end());
  slaves.erase(std::unique(slaves.begin(), slaves.end()), slaves.end());
  slave_nodes_ = slaves;
  double shortest = 1e300;
  for (const auto& e : slave_edges_) shortest = std::min(shortest, chord(mesh.nodes, e));
  if (shortest == 1e300) shortest = mesh.edge_length_range().first;
  length_scale_ = shortest > 0 && shortest < 1e300 ? shortest : model.model_size * 1e-3;
  add_tributary();
}

void ContactPairs::add_slave_edges(const ContactPairSpec& cs, bool required) {
  const core::Mesh& mesh = model_.mesh;
  std::vector<int> slave_edges;
  try {
    slave_edges = core::select_edges(model_, cs.slave);
  } catch (const InputError&) {
    if (required) throw;
  }
  for (int id : slave_edges) {
    slave_edges_.push_back(to_master_edge(mesh.boundary_edges[id], mesh.order));
    slave_edge_thickness_.push_back(
        model_.materials[mesh.element_material[mesh.boundary_edges[id].element]].thickness);
  }
}

void ContactPairs::add_master_normals(const ContactPairSpec& cs) {
  const core::Mesh& mesh = model_.mesh;
  if (!cs.master) return;  // a rigid obstacle: its rows' normals are its own
  std::vector<int> edges;
  try {
    edges = core::select_edges(model_, *cs.master);
  } catch (const InputError&) {
    return;  // a selection of nodes (node_to_node): its rows carry their direction
  }
  for (int id : edges) {
    const MasterEdge e = to_master_edge(mesh.boundary_edges[id], mesh.order);
    const Vec2 outward = outward_normal(mesh.nodes[e.nodes[1]] - mesh.nodes[e.nodes[0]]);
    const double length = chord(mesh.nodes, e);
    for (int a = 0; a < e.count; ++a) master_outward_[e.nodes[a]] += length * outward;
  }
}

void ContactPairs::add_tributary() {
  // Each slave node's share of the slave surface (a Tresca bound is a traction over it).
  const core::Mesh& mesh = model_.mesh;
  tributary_.assign(mesh.num_nodes(), 0.0);
  for (size_t k = 0; k < slave_edges_.size(); ++k) {
    const MasterEdge& e = slave_edges_[k];
    const double a = chord(mesh.nodes, e) * slave_edge_thickness_[k];
    if (e.count == 3) {
      tributary_[e.nodes[0]] += a / 6, tributary_[e.nodes[1]] += a / 6;
      tributary_[e.nodes[2]] += 2 * a / 3;
    } else {
      tributary_[e.nodes[0]] += a / 2, tributary_[e.nodes[1]] += a / 2;
    }
  }
}

void ContactPairs::add_gap_elements(const core::ExplicitModel& legacy) {
  // The seed's gap elements: direction from node a to node b (the file's (nx, ny) when they
  // coincide), gap = d · (x_b − x_a), the file's stiffness for penalty methods.
  const core::Mesh& mesh = model_.mesh;
  std::vector<NodeToNode::NodePair> gaps;
  for (const auto& g : legacy.gaps) {
    NodeToNode::NodePair np;
    np.master = g.node_a;
    np.slave = g.node_b;
    const Vec2 d = mesh.nodes[g.node_b] - mesh.nodes[g.node_a];
    np.direction = d.norm() > 0 ? Vec2(d.normalized()) : Vec2(g.direction.normalized());
    np.penalty = g.stiffness;
    gaps.push_back(np);
  }
  if (!gaps.empty())
    pairs_.push_back(
        std::make_unique<NodeToNode>(std::move(gaps), static_cast<int>(specs_.size())));
}

std::vector<GapRow> ContactPairs::detect_with(const VecX& u, bool small_strain, bool curvature,
                                              bool gauges) const {
  const core::Mesh& mesh = model_.mesh;
  std::vector<Vec2> x(mesh.num_nodes());
  for (int n = 0; n < mesh.num_nodes(); ++n) x[n] = mesh.nodes[n] + u.segment<2>(2 * n);
  const Configuration c{x, mesh.nodes, small_strain, &u, curvature};
  std::vector<GapRow> rows;
  for (size_t p = 0; p < pairs_.size(); ++p) {
    const bool gauge = gauges && p < gauges_.size() && gauges_[p];
    (gauge ? *gauges_[p] : *pairs_[p]).detect(c, first_slot_[p], rows);
  }
  return rows;
}

std::vector<GapRow> ContactPairs::detect(const VecX& u, bool small_strain, bool curvature) const {
  return detect_with(u, small_strain, curvature, false);
}

double ContactPairs::nodal_penetration(const VecX& u) const {
  double deepest = 0.0;
  for (const GapRow& r : detect_with(u, false, false, true)) deepest = std::max(deepest, -r.gap);
  return deepest;
}

SpMat ContactPairs::gap_jacobian(const std::vector<GapRow>& rows) const {
  const core::DofMap& dofs = model_.dofs;
  std::vector<Eigen::Triplet<double>> t;
  for (size_t i = 0; i < rows.size(); ++i)
    for (const auto& [node, coefficient] : rows[i].terms)
      for (int c = 0; c < 2; ++c) {
        const int eq = dofs.equation(2 * node + c);
        if (eq >= 0 && coefficient[c] != 0.0)
          t.emplace_back(static_cast<int>(i), eq, coefficient[c]);
      }
  SpMat g(static_cast<int>(rows.size()), dofs.num_free());
  g.setFromTriplets(t.begin(), t.end());
  return g;
}

SpMat ContactPairs::geometric_stiffness(const std::vector<GapRow>& rows, const VecX& force) const {
  const core::DofMap& dofs = model_.dofs;
  std::vector<Eigen::Triplet<double>> t;
  for (size_t i = 0; i < rows.size(); ++i) {
    const GapRow& r = rows[i];
    const double lambda = force[static_cast<int>(i)];
    if (lambda == 0.0 || r.curvature.size() == 0) continue;
    const int n = static_cast<int>(r.terms.size());
    for (int a = 0; a < 2 * n; ++a) {
      const int ea = dofs.equation(2 * r.terms[a / 2].first + a % 2);
      if (ea < 0) continue;
      for (int b = 0; b < 2 * n; ++b) {
        const int eb = dofs.equation(2 * r.terms[b / 2].first + b % 2);
        if (eb >= 0 && r.curvature(a, b) != 0.0)
          t.emplace_back(ea, eb, -lambda * r.curvature(a, b));
      }
    }
  }
  SpMat k(dofs.num_free(), dofs.num_free());
  k.setFromTriplets(t.begin(), t.end());
  return k;
}

void ContactPairs::add_gap_rows(const std::vector<GapRow>& rows, const VecX& u_full,
                                ConstrainedProblem& p) const {
  const core::DofMap& dofs = model_.dofs;
  const int m = static_cast<int>(rows.size());
  std::vector<Eigen::Triplet<double>> t;
  p.gap0 = VecX(m);
  p.gap_penalty = VecX::Zero(m);
  p.gap_area = VecX::Zero(m);
  p.gap_node_area = VecX::Zero(m);
  p.gap_surface.assign(m, -1);
  for (int i = 0; i < m; ++i) {
    const GapRow& r = rows[i];
    if (r.pair < static_cast<int>(specs_.size())) {  // not one of the seed's gap elements
      p.gap_node_area[i] = tributary_[r.slave];
      p.gap_area[i] = r.weight > 0 ? r.weight : p.gap_node_area[i];
      p.gap_surface[i] = r.pair;
    }
    // g(u) = g_det + Σ a_j (u_j − u_det,j): free DOFs become columns, the rest is constant.
    double g0 = r.gap;
    for (const auto& [node, coefficient] : r.terms)
      for (int c = 0; c < 2; ++c) {
        const int dof = 2 * node + c;
        const double a = coefficient[c];
        if (a == 0.0) continue;
        const int eq = dofs.equation(dof);
        if (eq >= 0) t.emplace_back(i, eq, a), g0 -= a * u_full[dof];
        // a prescribed DOF stays at its detection value
      }
    p.gap0[i] = g0;
    p.gap_penalty[i] = r.penalty;
  }
  p.gap_jacobian = SpMat(m, dofs.num_free());
  p.gap_jacobian.setFromTriplets(t.begin(), t.end());
}

bool ContactPairs::has_friction() const {
  for (const ContactPairSpec& c : specs_)
    if (c.friction.enabled()) return true;
  return false;
}

void ContactPairs::add_friction_rows(const std::vector<GapRow>& rows, const VecX& u_full,
                                     const VecX* u_reference, ConstrainedProblem& p) const {
  // The tangential row of a gap row: each coefficient turned clockwise (c → (c_y, −c_x)), so
  // its slip is along the normal turned clockwise; the slip is measured from u_reference.
  const core::DofMap& dofs = model_.dofs;
  const int m = static_cast<int>(rows.size());
  std::vector<Eigen::Triplet<double>> t;
  p.slip0 = VecX::Zero(m);
  p.friction_law.assign(m, nullptr);
  p.tangent_penalty_ratio = VecX::Ones(m);
  for (int i = 0; i < m; ++i) {
    const GapRow& r = rows[i];
    double s0 = 0.0;
    for (const auto& [node, coefficient] : r.terms) {
      const Vec2 a(coefficient.y(), -coefficient.x());
      for (int c = 0; c < 2; ++c) {
        const int dof = 2 * node + c;
        if (a[c] == 0.0) continue;
        const double ref = u_reference ? (*u_reference)[dof] : 0.0;
        const int eq = dofs.equation(dof);
        if (eq >= 0)
          t.emplace_back(i, eq, a[c]), s0 -= a[c] * ref;
        else
          s0 += a[c] * (u_full[dof] - ref);
      }
    }
    p.slip0[i] = s0;
    if (r.pair >= static_cast<int>(specs_.size())) continue;  // the seed's gap elements
    const FrictionSpec& f = specs_[r.pair].friction;
    p.friction_law[i] = f.model;
    p.tangent_penalty_ratio[i] = f.penalty_ratio;
  }
  p.slip_jacobian = SpMat(m, dofs.num_free());
  p.slip_jacobian.setFromTriplets(t.begin(), t.end());
}

}  // namespace c2d::constraints
