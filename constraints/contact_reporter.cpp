#include "constraints/contact_reporter.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace c2d::constraints {

namespace {

/// Quadratic edges: recover on the linear (corner-node) pressure space, the stable partner of
/// quadratic displacements. A middle node's force moves half to each end (the linear basis at
/// the midpoint), which is exact for any linear pressure and filters the corner/middle
/// imbalance node-to-segment forces carry (on hertz_block the quadratic projection of those
/// forces overshoots p0 by 16%). Only active corners carry unknowns: an active middle beside an
/// open corner gives its whole force to its active corner, and a middle node reports the
/// field's value between its corners when it is active, 0 when it is open. A middle active
/// between two open corners (a contact zone inside half an edge) gets its force over its own
/// tributary length, 2/3 of the edge.
VecX recover_on_corner_nodes(const std::vector<Vec2>& x, const std::vector<MasterEdge>& edges,
                             const std::vector<double>& thickness, const std::vector<int>& nodes,
                             const VecX& force, const std::vector<char>& active) {
  std::map<int, int> slot;
  for (size_t i = 0; i < nodes.size(); ++i) slot[nodes[i]] = static_cast<int>(i);
  VecX corner_force = VecX::Zero(static_cast<int>(nodes.size()));
  std::vector<char> corner_active(nodes.size(), 0), is_middle(nodes.size(), 0);
  std::vector<MasterEdge> chords;
  for (const MasterEdge& e : edges) {
    const int a = slot.at(e.nodes[0]), b = slot.at(e.nodes[1]), m = slot.at(e.nodes[2]);
    is_middle[m] = 1;
    const double share_a = active[a] && active[b] ? 0.5 : active[a] ? 1.0 : active[b] ? 0.0 : 0.5;
    corner_force[a] += share_a * force[m];
    corner_force[b] += (1.0 - share_a) * force[m];
    MasterEdge chord;
    chord.nodes = {e.nodes[0], e.nodes[1], -1};
    chords.push_back(chord);
  }
  for (size_t i = 0; i < nodes.size(); ++i)
    if (!is_middle[i]) {
      corner_force[static_cast<int>(i)] += force[static_cast<int>(i)];
      corner_active[i] = active[i];
    }
  VecX p = recover_pressure(x, chords, thickness, nodes, corner_force, corner_active);
  for (size_t k = 0; k < edges.size(); ++k) {
    const MasterEdge& e = edges[k];
    const int a = slot.at(e.nodes[0]), b = slot.at(e.nodes[1]), m = slot.at(e.nodes[2]);
    if (!active[m]) {
      p[m] = 0.0;
    } else if (active[a] || active[b]) {
      p[m] = 0.5 * (p[a] + p[b]);
    } else {
      const double tributary = 2.0 / 3.0 * (x[e.nodes[1]] - x[e.nodes[0]]).norm() * thickness[k];
      p[m] = tributary > 0 ? force[m] / tributary : 0.0;
    }
  }
  return p;
}

/// The mass matrix of the pressure space over the edges, on the unknowns `index` numbers.
SpMat pressure_mass_matrix(const std::vector<Vec2>& x, const std::vector<MasterEdge>& edges,
                           const std::vector<double>& thickness, const std::map<int, int>& index) {
  // 4-point Gauss on [0, 1]: exact for the quadratic-times-quadratic products on straight edges,
  // and accurate on the gently curved edges of a contact surface.
  const double gp[4] = {0.0694318442029737, 0.3300094782075719, 0.6699905217924281,
                        0.9305681557970263};
  const double gw[4] = {0.1739274225687269, 0.3260725774312731, 0.3260725774312731,
                        0.1739274225687269};
  std::vector<Eigen::Triplet<double>> t;
  for (size_t k = 0; k < edges.size(); ++k) {
    const MasterEdge& e = edges[k];
    int slot[3] = {-1, -1, -1};
    bool any = false;
    for (int a = 0; a < e.count; ++a) {
      const auto it = index.find(e.nodes[a]);
      if (it != index.end()) slot[a] = it->second, any = true;
    }
    if (!any) continue;
    for (int q = 0; q < 4; ++q) {
      std::array<double, 3> n, dn, ddn;
      edge_shape(e.count, gp[q], n, dn, ddn);
      const double w = gw[q] * combine(e, x, dn).norm() * thickness[k];
      for (int a = 0; a < e.count; ++a)
        for (int b = 0; b < e.count; ++b)
          if (slot[a] >= 0 && slot[b] >= 0) t.emplace_back(slot[a], slot[b], w * n[a] * n[b]);
    }
  }
  const int ns = static_cast<int>(index.size());
  SpMat mass(ns, ns);
  mass.setFromTriplets(t.begin(), t.end());
  return mass;
}

}  // namespace

VecX recover_pressure(const std::vector<Vec2>& x, const std::vector<MasterEdge>& edges,
                      const std::vector<double>& thickness, const std::vector<int>& nodes,
                      const VecX& force, const std::vector<char>& active) {
  if (!edges.empty() && edges.front().count == 3)
    return recover_on_corner_nodes(x, edges, thickness, nodes, force, active);
  // Unknowns: the pressures of the active nodes; inactive nodes hold p = 0, so the projection
  // cannot ring beyond the edge of the contact zone.
  std::map<int, int> index;
  for (size_t i = 0; i < nodes.size(); ++i)
    if (active[i]) index.emplace(nodes[i], static_cast<int>(index.size()));
  VecX out = VecX::Zero(static_cast<int>(nodes.size()));
  if (index.empty()) return out;
  const int ns = static_cast<int>(index.size());
  SpMat mass = pressure_mass_matrix(x, edges, thickness, index);
  VecX f = VecX::Zero(ns);
  for (size_t i = 0; i < nodes.size(); ++i) {
    const auto it = index.find(nodes[i]);
    if (it != index.end()) f[it->second] += force[static_cast<int>(i)];
  }
  // An active node on no slave edge has no pressure (a zero row): keep the system regular.
  const VecX diag = mass.diagonal();
  for (int i = 0; i < ns; ++i)
    if (diag[i] == 0.0) mass.coeffRef(i, i) = 1.0, f[i] = 0.0;
  Eigen::SimplicialLDLT<SpMat> ldlt(mass);
  if (ldlt.info() != Eigen::Success) return out;
  VecX p = ldlt.solve(f);
  // The projection holds p = 0 on the open nodes, so the last active node's basis function
  // reaches into the open neighbour's edge, where M p = f is not imposed: ∫ p ds would exceed
  // Σ f by t h p_last / 6 per contact edge. That excess is the last active nodes' own, so they
  // give it back: one common change of their pressures makes ∫ p ds = cᵀ p = Σ f (c_i = ∫ φ_i
  // t ds over all of node i's edges), and the recovered pressure carries exactly the force the
  // rows transmit.
  VecX c = VecX::Zero(ns), last = VecX::Zero(ns);
  for (size_t k = 0; k < edges.size(); ++k) {
    const auto a = index.find(edges[k].nodes[0]), b = index.find(edges[k].nodes[1]);
    const double half = 0.5 * thickness[k] * (x[edges[k].nodes[1]] - x[edges[k].nodes[0]]).norm();
    if (a != index.end()) c[a->second] += half;
    if (b != index.end()) c[b->second] += half;
    if ((a == index.end()) != (b == index.end())) last[(a != index.end() ? a : b)->second] = 1.0;
  }
  if (c.dot(last) > 0) p += ((f.sum() - c.dot(p)) / c.dot(last)) * last;
  if (!p.allFinite()) return out;
  for (size_t i = 0; i < nodes.size(); ++i) {
    const auto it = index.find(nodes[i]);
    if (it != index.end()) out[static_cast<int>(i)] = p[it->second];
  }
  return out;
}

ContactReporter::ContactReporter(const core::Model& model, const ContactPairs& pairs,
                                 const EqualityConstraints& equalities,
                                 const StrategyOptions& options)
    : model_(model),
      pairs_(pairs),
      equalities_(equalities),
      penetration_limit_(options.penetration_limit) {}

void ContactReporter::report(const std::vector<GapRow>& rows, const ConstraintSolution& s,
                             ContactReport& r) const {
  const core::Mesh& mesh = model_.mesh;
  const std::vector<MasterEdge>& slave_edges = pairs_.slave_edges();
  r.penetration_limit = penetration_limit();
  std::map<int, int> slot;
  r.nodes.clear();
  for (int n : pairs_.slave_nodes()) {
    slot[n] = static_cast<int>(r.nodes.size());
    ContactNodeResult cn;
    cn.node = n;
    cn.x = mesh.nodes[n];
    cn.gap = 1e300;
    r.nodes.push_back(cn);
  }
  std::vector<double> mortar_weight(r.nodes.size(), 0.0);
  std::vector<Vec2> contact_normal(r.nodes.size(), Vec2::Zero());  // of an active row
  for (size_t i = 0; i < rows.size(); ++i) {
    const int at = slot[rows[i].slave];
    ContactNodeResult& cn = r.nodes[at];
    const int k = static_cast<int>(i);
    cn.gap = std::min(cn.gap, s.gap.size() > k ? s.gap[k] : rows[i].gap);
    cn.force += s.contact_force.size() > k ? s.contact_force[k] : 0.0;
    cn.penalty = std::max(cn.penalty, s.penalty.size() > k ? s.penalty[k] : 0.0);
    const bool closed = static_cast<int>(s.active.size()) > k && s.active[k];
    if (closed) contact_normal[at] = rows[i].normal;
    cn.active = cn.active || closed;
    mortar_weight[at] += rows[i].weight;
    if (s.tangent_force.size() > k) cn.tangent_force -= s.tangent_force[k];
    // An open row's tangential motion is approach, not slip.
    if (s.slip.size() > k && closed) cn.slip = s.slip[k], cn.accumulated_slip = std::abs(cn.slip);
    if (static_cast<int>(s.friction_state.size()) > k)
      cn.state = std::max(cn.state, s.friction_state[k]);
  }
  std::vector<char> mortar_edge(slave_edges.size(), 0);
  for (size_t k = 0; k < slave_edges.size(); ++k) {
    const MasterEdge& e = slave_edges[k];
    mortar_edge[k] = mortar_weight[slot[e.nodes[0]]] > 0 || mortar_weight[slot[e.nodes[1]]] > 0;
  }
  const std::vector<char> side = side_edges(slot, contact_normal, r.nodes);
  assign_pressure(slot, mortar_weight, mortar_edge, side, r);
  r.has_surface = !slave_edges.empty();
  report_equalities(s, r);
  r.active_nodes = 0;
  r.total_force = 0.0;
  r.p_max = 0.0;
  r.friction = pairs_.has_friction();
  r.stick_nodes = r.slip_nodes = 0;
  for (const ContactNodeResult& cn : r.nodes) {
    r.stick_nodes += cn.state == FrictionState::kStick;
    r.slip_nodes += cn.state == FrictionState::kSlip;
    r.active_nodes += cn.active;
    r.total_force += cn.force;
    r.p_max = std::max(r.p_max, cn.pressure);
  }
  add_resultant(rows, s, r);
  const std::vector<double> owned = owned_lengths(slot, mortar_edge, side);
  r.length = 0.0;
  for (size_t i = 0; i < r.nodes.size(); ++i)
    if (r.nodes[i].active) r.length += owned[i];
  if (r.friction) {  // the stick zone, measured as the contact zone is
    std::vector<ContactNodeResult> sticking = r.nodes;
    for (ContactNodeResult& cn : sticking) cn.active = cn.state == FrictionState::kStick;
    // a quadratic mortar edge's middle node sticks with its corners
    for (size_t k = 0; k < slave_edges.size(); ++k)
      if (mortar_edge[k] && slave_edges[k].count == 3)
        sticking[slot.at(slave_edges[k].nodes[2])].active =
            sticking[slot.at(slave_edges[k].nodes[0])].active ||
            sticking[slot.at(slave_edges[k].nodes[1])].active;
    r.stick_length = stick_zone_length(slot, side, sticking, owned);
  }
  r.max_penetration = s.max_penetration;
  r.rows = static_cast<int>(rows.size());
}

void ContactReporter::report_equalities(const ConstraintSolution& s, ContactReport& r) const {
  r.equalities.clear();
  r.equality_names.clear();
  r.equality_types.clear();
  for (const EqualitySpec& e : equalities_.specs()) {
    r.equality_names.push_back(e.name);
    r.equality_types.push_back(e.type);
  }
  r.max_equality_violation = 0.0;
  const std::vector<EqualityRow>& rows = equalities_.constraint_rows();
  for (size_t j = 0; j < rows.size(); ++j) {  // the [[plate]] rows follow these
    const int k = static_cast<int>(j);
    EqualityRowResult e;
    e.owner = rows[j].owner;
    e.multiplier = s.eq_multiplier.size() > k ? s.eq_multiplier[k] : 0.0;
    e.residual = s.eq_residual.size() > k ? s.eq_residual[k] : 0.0;
    r.max_equality_violation = std::max(r.max_equality_violation, std::abs(e.residual));
    r.equalities.push_back(e);
  }
}

void ContactReporter::add_resultant(const std::vector<GapRow>& rows, const ConstraintSolution& s,
                                    ContactReport& r) const {
  // The frame of the tangential force: the master surface's normal in the reference
  // configuration, where each row meets it (its master nodes' normals, weighted by their
  // coefficients; a rigid obstacle's or a node pair's own normal), averaged with the rows'
  // forces. Neither the slave's normals (they tilt across a curved slave's contact zone) nor the
  // deformed ones (they turn with the load) give the load a flat master carries.
  const std::vector<Vec2>& master_outward = pairs_.master_outward();
  Vec2 normal_sum = Vec2::Zero();
  r.resultant = Vec2::Zero();
  for (size_t i = 0; i < rows.size(); ++i) {
    // the row's force on the slave: λ along its normal, −λ_t along its tangent (n turned cw)
    const int k = static_cast<int>(i);
    const Vec2& n = rows[i].normal;
    const double lambda = s.contact_force.size() > k ? s.contact_force[k] : 0.0;
    const double q = s.tangent_force.size() > k ? -s.tangent_force[k] : 0.0;
    r.resultant += lambda * n + q * Vec2(n.y(), -n.x());
    Vec2 master = Vec2::Zero();
    for (const auto& [node, c] : rows[i].terms)
      if (node != rows[i].slave && master_outward[node].squaredNorm() > 0)
        master += c.norm() * master_outward[node];
    if (master.squaredNorm() == 0.0 || master.dot(n) <= 0.0) master = n;
    normal_sum += lambda * master.normalized();
  }
  r.tangent_force = 0.0;
  if (normal_sum.norm() > 0) {
    const Vec2 n = normal_sum.normalized();
    r.tangent_force = r.resultant.dot(Vec2(n.y(), -n.x()));
  } else {
    for (const ContactNodeResult& cn : r.nodes) r.tangent_force += cn.tangent_force;
  }
}

std::vector<char> ContactReporter::side_edges(const std::map<int, int>& slot,
                                              const std::vector<Vec2>& contact_normal,
                                              const std::vector<ContactNodeResult>& nodes) const {
  // A slave surface selected by a region (a box over a block's lower part) also holds edges of
  // the body's sides. Where the contact zone reaches such a corner, the recovery would spread
  // the corner's force over the side edge as if the zone went on round the corner, and its
  // length would count half of it: block on a rigid floor, p_max 114 where the bottom edge alone
  // gives the exact 100. An edge with one active end whose outward normal is turned more than
  // 45 degrees from facing the master there (the row's normal, master toward slave) is such a
  // side; an edge with both ends active is in the contact zone whatever its direction. Normals
  // of the reference configuration, as the recovery's lengths (45 degrees leaves room for the
  // rotations a contact surface goes through).
  constexpr double kFacing = 0.70710678118654752;  // cos 45°
  const core::Mesh& mesh = model_.mesh;
  const std::vector<MasterEdge>& slave_edges = pairs_.slave_edges();
  std::vector<char> side(slave_edges.size(), 0);
  for (size_t k = 0; k < slave_edges.size(); ++k) {
    const MasterEdge& e = slave_edges[k];
    const int a = slot.at(e.nodes[0]), b = slot.at(e.nodes[1]);
    if (nodes[a].active == nodes[b].active) continue;
    const Vec2 n = contact_normal[nodes[a].active ? a : b];
    const Vec2 t = mesh.nodes[e.nodes[1]] - mesh.nodes[e.nodes[0]];
    if (n.squaredNorm() == 0.0 || t.squaredNorm() == 0.0) continue;
    side[k] = outward_normal(t).dot(n.normalized()) > -kFacing;  // the body lies left of its edges
  }
  return side;
}

void ContactReporter::assign_pressure(const std::map<int, int>& slot,
                                      const std::vector<double>& mortar_weight,
                                      const std::vector<char>& mortar_edge,
                                      const std::vector<char>& side_edge, ContactReport& r) const {
  // Node-based rows: a pressure recovered from the nodal forces on the edges they load.
  const std::vector<MasterEdge>& slave_edges = pairs_.slave_edges();
  std::vector<MasterEdge> edges;
  std::vector<double> thickness;
  for (size_t k = 0; k < slave_edges.size(); ++k)
    if (!mortar_edge[k] && !side_edge[k])
      edges.push_back(slave_edges[k]), thickness.push_back(pairs_.slave_edge_thickness()[k]);
  const int n = static_cast<int>(r.nodes.size());
  VecX force(n), tangent(n);
  std::vector<char> active(r.nodes.size(), 0);
  for (int i = 0; i < n; ++i) {
    if (r.nodes[i].gap == 1e300) r.nodes[i].gap = 0.0;  // no master within reach
    force[i] = mortar_weight[i] > 0 ? 0.0 : r.nodes[i].force;
    tangent[i] = mortar_weight[i] > 0 ? 0.0 : r.nodes[i].tangent_force;
    active[i] = mortar_weight[i] > 0 ? 0 : r.nodes[i].active;
  }
  const std::vector<int>& nodes = pairs_.slave_nodes();
  const VecX p = recover_pressure(model_.mesh.nodes, edges, thickness, nodes, force, active);
  const VecX q = pairs_.has_friction()
                     ? recover_pressure(model_.mesh.nodes, edges, thickness, nodes, tangent, active)
                     : VecX(VecX::Zero(n));
  // Mortar rows: the multiplier is the pressure's integral against the row's hat.
  for (int i = 0; i < n; ++i) {
    r.nodes[i].pressure = mortar_weight[i] > 0 ? r.nodes[i].force / mortar_weight[i] : p[i];
    r.nodes[i].shear = mortar_weight[i] > 0 ? r.nodes[i].tangent_force / mortar_weight[i] : q[i];
  }
  // The middle node of a quadratic mortar edge lies on the linear multiplier between its corners.
  for (size_t k = 0; k < slave_edges.size(); ++k) {
    const MasterEdge& e = slave_edges[k];
    if (!mortar_edge[k] || e.count != 3) continue;
    const ContactNodeResult &a = r.nodes[slot.at(e.nodes[0])], &b = r.nodes[slot.at(e.nodes[1])];
    ContactNodeResult& m = r.nodes[slot.at(e.nodes[2])];
    m.pressure = 0.5 * (a.pressure + b.pressure);
    m.shear = 0.5 * (a.shear + b.shear);
    m.gap = 0.5 * (a.gap + b.gap);
    m.active = a.active || b.active;  // inside the support of an active multiplier
    m.slip = 0.5 * (a.slip + b.slip);
    m.accumulated_slip = 0.5 * (a.accumulated_slip + b.accumulated_slip);
    // sticking where both corners stick, slipping where either slips
    m.state = a.state == b.state ? a.state : std::max(a.state, b.state);
  }
}

double ContactReporter::stick_zone_length(const std::map<int, int>& slot,
                                          const std::vector<char>& side_edge,
                                          const std::vector<ContactNodeResult>& sticking,
                                          const std::vector<double>& owned) const {
  // The sticking nodes joined along the slave edges into runs; the longest run is the stick
  // zone. A node that first touched in the last increment has not slipped yet and sticks at
  // the edge of the contact zone, apart from the zone (Cattaneo–Mindlin on a rigid flat: two
  // such nodes added 0.006 to c/b at b/80).
  const int n = static_cast<int>(sticking.size());
  std::vector<int> root(n);
  for (int i = 0; i < n; ++i) root[i] = i;
  auto find = [&](int i) {
    while (root[i] != i) i = root[i] = root[root[i]];
    return i;
  };
  const std::vector<MasterEdge>& slave_edges = pairs_.slave_edges();
  for (size_t k = 0; k < slave_edges.size(); ++k) {
    if (side_edge[k]) continue;
    // A T3 edge joins its corners; a T6 edge's middle node joins each corner beside it, so
    // a run passes a T6 edge through its middle.
    const MasterEdge& e = slave_edges[k];
    const int hub = slot.at(e.nodes[e.count == 3 ? 2 : 1]);
    for (int a = 0; a < (e.count == 3 ? 2 : 1); ++a) {
      const int c = slot.at(e.nodes[a]);
      if (sticking[hub].active && sticking[c].active) root[find(hub)] = find(c);
    }
  }
  std::vector<double> run(n, 0.0);  // by the run's root
  for (int i = 0; i < n; ++i)
    if (sticking[i].active) run[find(i)] += owned[i];
  return n > 0 ? *std::max_element(run.begin(), run.end()) : 0.0;
}

std::vector<double> ContactReporter::owned_lengths(const std::map<int, int>& slot,
                                                   const std::vector<char>& mortar_edge,
                                                   const std::vector<char>& side_edge) const {
  // Every slave node owns the part of its edges nearer to it than to the edge's other nodes
  // (T3 edges split at the middle; T6 at the quarter points); the contact length is the arc
  // length owned by active nodes. Node-to-node contact only knows that the contact edge lies
  // between the last active node and the first open one, and this puts it halfway: unbiased,
  // within a quarter (T6) or half (T3) of the edge there. (The recovered pressure is positive
  // up to the first open node's far side, so its support overestimated b by about one node
  // spacing.) A mortar edge's multiplier is linear between its corners, so each corner owns
  // half of it, T6 included.
  const core::Mesh& mesh = model_.mesh;
  const std::vector<MasterEdge>& slave_edges = pairs_.slave_edges();
  std::vector<double> owned(slot.size(), 0.0);
  for (size_t k = 0; k < slave_edges.size(); ++k) {
    if (side_edge[k]) continue;  // a side of the body beside the zone (side_edges)
    const MasterEdge& e = slave_edges[k];
    auto point = [&](double s) {
      if (e.count == 2) return Vec2((1 - s) * mesh.nodes[e.nodes[0]] + s * mesh.nodes[e.nodes[1]]);
      return Vec2((1 - s) * (1 - 2 * s) * mesh.nodes[e.nodes[0]] +
                  s * (2 * s - 1) * mesh.nodes[e.nodes[1]] +
                  4 * s * (1 - s) * mesh.nodes[e.nodes[2]]);
    };
    // Parametric stretches of the edge owned by each of its nodes (ends first, then mid-side).
    const double t3[2][2] = {{0.0, 0.5}, {0.5, 1.0}};
    const double t6[3][2] = {{0.0, 0.25}, {0.75, 1.0}, {0.25, 0.75}};
    const bool halves = e.count == 2 || mortar_edge[k];
    for (int a = 0; a < (halves ? 2 : 3); ++a) {
      const double s0 = halves ? t3[a][0] : t6[a][0], s1 = halves ? t3[a][1] : t6[a][1];
      constexpr int kSamples = 16;  // arc length of a curved T6 edge
      double& length = owned[slot.at(e.nodes[a])];
      for (int q = 0; q < kSamples; ++q)
        length +=
            (point(s0 + (s1 - s0) * (q + 1) / kSamples) - point(s0 + (s1 - s0) * q / kSamples))
                .norm();
    }
  }
  return owned;
}

}  // namespace c2d::constraints
