#include "constraints/discretizations/mortar.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "constraints/gap_linearisation.hpp"
#include "core/mesh.hpp"

namespace c2d::constraints {

struct Mortar::Accumulator {
  double gap = 0.0;     ///< ∫ Φ_j g t ds
  double weight = 0.0;  ///< ∫ Φ_j t ds
  Vec2 normal = Vec2::Zero();
  std::vector<std::pair<int, Vec2>> terms;
  /// Finite strain: ∫ Φ_j g t ds and ∫ Φ_j t ds as functions of the positions (exact
  /// derivatives; the row is their quotient).
  LocalGap exact_gap, exact_weight;
  /// A tie's coupling (Mortar::coupling): the coefficients ∫ Φ_j N ds themselves, stored as
  /// their x component, instead of their products with the normal.
  bool scalar = false;

  void add_exact(double scale, const LocalGap& measure, const LocalGap& weighted) {
    exact_gap.add(scale, weighted);
    exact_weight.add(scale, measure);
  }
  void add(int node, const Vec2& c) {
    for (auto& [n, value] : terms)
      if (n == node) {
        value += c;
        return;
      }
    terms.emplace_back(node, c);
  }
  /// One quadrature point: weight w (with Φ_j), gap g, normal n toward the free side, and the
  /// coefficients of δg: +n·δu at the slave nodes (shape values ns), −n·δu at the master's (nm).
  void add_point(double w, double g, const Vec2& n, const MasterEdge& slave,
                 const std::array<double, 3>& ns, const MasterEdge* master,
                 const std::array<double, 3>& nm) {
    gap += w * g;
    weight += w;
    normal += w * n;
    const Vec2 along = scalar ? Vec2(Vec2::UnitX()) : n;
    for (int k = 0; k < slave.count; ++k) add(slave.nodes[k], w * ns[k] * along);
    if (master)
      for (int l = 0; l < master->count; ++l) add(master->nodes[l], -w * nm[l] * along);
  }
};

namespace {

// 4-point Gauss on [0, 1]: exact to degree 7.
constexpr double kGaussPoint[4] = {0.0694318442029737, 0.3300094782075719, 0.6699905217924281,
                                   0.9305681557970263};
constexpr double kGaussWeight[4] = {0.1739274225687269, 0.3260725774312731,
                                    0.3260725774312731, 0.1739274225687269};

struct EdgePoint {
  Vec2 x = Vec2::Zero();
  Vec2 tangent = Vec2::Zero();  ///< dx/dξ
  std::array<double, 3> shape{0, 0, 0};
};

EdgePoint evaluate(const MasterEdge& e, const std::vector<Vec2>& x, double xi) {
  EdgePoint p;
  std::array<double, 3> dn, ddn;
  edge_shape(e.count, xi, p.shape, dn, ddn);
  p.x = combine(e, x, p.shape);
  p.tangent = combine(e, x, dn);
  return p;
}

/// Where the ray p + α n meets edge e's curve: its parameter η (possibly just outside [0, 1])
/// and α. False when the ray runs along the edge.
bool ray_hit(const MasterEdge& e, const std::vector<Vec2>& x, const Vec2& p, const Vec2& n,
             double& eta, double& alpha) {
  const Vec2 t(-n.y(), n.x());
  const double fa = (x[e.nodes[0]] - p).dot(t), fb = (x[e.nodes[1]] - p).dot(t);
  if (fa == fb) return false;
  eta = fa / (fa - fb);  // the chord's crossing; exact for a straight edge
  std::array<double, 3> s, ds, dds;
  // Newton on the quadratic edge, to round-off: it stops once a step no longer halves the one
  // before (the last digits' noise; a test on |step| < 1e-15 alone ran all 30 iterations
  // whenever round-off kept the step above it, a tenth of a mortar run's time).
  double last = std::numeric_limits<double>::infinity();
  for (int it = 0; e.count == 3 && it < 30; ++it) {
    edge_shape(3, eta, s, ds, dds);
    const double f = (combine(e, x, s) - p).dot(t), df = combine(e, x, ds).dot(t);
    if (df == 0.0) return false;
    const double step = f / df;
    eta -= step;
    if (std::abs(step) < 1e-15 || std::abs(step) > 0.5 * last) break;
    last = std::abs(step);
  }
  edge_shape(e.count, eta, s, ds, dds);
  alpha = (combine(e, x, s) - p).dot(n);
  return std::isfinite(eta) && std::isfinite(alpha);
}

bool shares_node(const MasterEdge& a, const MasterEdge& b) {
  for (int i = 0; i < a.count; ++i)
    for (int j = 0; j < b.count; ++j)
      if (a.nodes[i] == b.nodes[j]) return true;
  return false;
}

}  // namespace

Mortar::Mortar(const DiscretizationInput& in) : index_(in.index) {
  const core::Mesh& mesh = in.model.mesh;
  for (int id : core::select_edges(in.model, in.pair.slave)) {
    const core::BoundaryEdge& be = mesh.boundary_edges[id];
    SlaveEdge se;
    se.edge = to_master_edge(be, mesh.order);
    se.thickness = in.model.materials[mesh.element_material[be.element]].thickness;
    slave_edges_.push_back(se);
    corners_.push_back(be.nodes[0]);
    corners_.push_back(be.nodes[1]);
    for (int a = 0; a < se.edge.count; ++a) nodes_.push_back(be.nodes[a]);
  }
  for (auto* v : {&corners_, &nodes_}) {
    std::sort(v->begin(), v->end());
    v->erase(std::unique(v->begin(), v->end()), v->end());
  }
  for (SlaveEdge& se : slave_edges_)
    for (int a = 0; a < 2; ++a)
      se.row[a] = static_cast<int>(
          std::lower_bound(corners_.begin(), corners_.end(), se.edge.nodes[a]) - corners_.begin());
  if (in.pair.obstacle >= 0) {
    obstacle_ = &in.obstacles[in.pair.obstacle];
    if (in.pair.search_distance > 0) search_ = in.pair.search_distance;
    return;
  }
  double longest = 0.0;
  for (int id : core::select_edges(in.model, *in.pair.master)) {
    master_edges_.push_back(to_master_edge(mesh.boundary_edges[id], mesh.order));
    const MasterEdge& e = master_edges_.back();
    longest = std::max(longest, (mesh.nodes[e.nodes[1]] - mesh.nodes[e.nodes[0]]).norm());
  }
  search_ = in.pair.search_distance > 0 ? in.pair.search_distance : 2.0 * longest;
}

void Mortar::integrate_obstacle(const Configuration& c, const SlaveEdge& se,
                                std::vector<Accumulator>& acc) const {
  for (int q = 0; q < 4; ++q) {
    const double xi = kGaussPoint[q];
    const EdgePoint now = evaluate(se.edge, c.x, xi);
    const EdgePoint geo = c.small_strain ? evaluate(se.edge, c.reference, xi) : now;
    double g;
    Vec2 n;
    obstacle_->gap(geo.x, g, n);
    if (c.small_strain) g += n.dot(now.x - geo.x);
    if (g > search_) continue;
    const double w = kGaussWeight[q] * geo.tangent.norm() * se.thickness;
    const double phi[2] = {1.0 - xi, xi};
    for (int a = 0; a < 2; ++a)
      acc[se.row[a]].add_point(w * phi[a], g, n, se.edge, now.shape, nullptr, {});
    if (!c.small_strain) {
      LocalGap measure[2], weighted[2];
      mortar_point(se.edge, {0.0}, {1.0}, xi, nullptr, 0.0, obstacle_, c.positions(), measure,
                   weighted, c.curvature);
      for (int a = 0; a < 2; ++a)
        acc[se.row[a]].add_exact(kGaussWeight[q] * se.thickness, measure[a], weighted[a]);
    }
  }
}

void Mortar::integrate_master(const Configuration& c, const MasterSurfaceSearch& search,
                              const SlaveEdge& se, std::vector<Accumulator>& acc) const {
  // Segments and pairing at the current positions, so that a slave that slid along its master
  // meets the master it now faces (node_to_segment's projection does the same); in small
  // strain the normals and weights stay the reference slave edge's (the linear kinematics).
  const std::vector<Vec2>& now = c.x;
  const std::vector<Vec2>& geo = c.small_strain ? c.reference : c.x;
  const MasterEdge& e = se.edge;
  Vec2 lo = now[e.nodes[0]], hi = lo;
  for (int a = 1; a < e.count; ++a) lo = lo.cwiseMin(now[e.nodes[a]]), hi = hi.cwiseMax(now[e.nodes[a]]);
  std::vector<int> candidates;
  for (int id : search.edges_near(lo, hi))
    if (!shares_node(e, master_edges_[id])) candidates.push_back(id);
  if (candidates.empty()) return;
  // Cut the slave edge where the slave normal passes a master vertex.
  std::vector<SegmentEnd> cuts = {{0.0, -1}, {1.0, -1}};
  for (int id : candidates)
    for (int end = 0; end < 2; ++end) {
      const int vertex = master_edges_[id].nodes[end];
      const double xi = project_on_edge(e, now, now[vertex]).xi;
      if (xi > 0.0 && xi < 1.0) cuts.push_back({xi, vertex});
    }
  std::sort(cuts.begin(), cuts.end(),
            [](const SegmentEnd& p, const SegmentEnd& q) { return p.xi < q.xi; });
  for (size_t k = 0; k + 1 < cuts.size(); ++k) {
    const double a = cuts[k].xi, b = cuts[k + 1].xi;
    if (b - a < 1e-12) continue;
    const MasterEdge* master = facing_edge(now, e, 0.5 * (a + b), candidates);
    if (!master) continue;  // past a free end of the master surface: nothing to touch
    for (int q = 0; q < 4; ++q) {
      const double xi = a + (b - a) * kGaussPoint[q];
      const EdgePoint slave = evaluate(e, now, xi);
      double eta, alpha;
      if (!ray_hit(*master, now, slave.x, outward_normal(slave.tangent), eta, alpha)) continue;
      const EdgePoint own = c.small_strain ? evaluate(e, geo, xi) : slave;
      // From the master toward the slave. In small strain the master's reference normal where
      // the ray meets it: the slave's reference normal tilts (by x/R on a cylinder) away from the
      // interface the deformed bodies share, and its tangent then mixes the pressure into the
      // friction row (Cattaneo-Mindlin: 2.5 % of mu p0 of shear error, a resultant off by 2e-7).
      const Vec2 n =
          c.small_strain ? edge_normal(*master, geo, eta) : Vec2(-outward_normal(own.tangent));
      const EdgePoint on_master = evaluate(*master, now, eta);
      const double g = n.dot(slave.x - on_master.x);
      const double w = (b - a) * kGaussWeight[q] * own.tangent.norm() * se.thickness;
      const double phi[2] = {1.0 - xi, xi};
      for (int r = 0; r < 2; ++r)
        acc[se.row[r]].add_point(w * phi[r], g, n, e, slave.shape, master, on_master.shape);
      if (!c.small_strain) {
        LocalGap measure[2], weighted[2];
        mortar_point(e, cuts[k], cuts[k + 1], kGaussPoint[q], master, eta, nullptr,
                     c.positions(), measure, weighted, c.curvature);
        for (int r = 0; r < 2; ++r)
          acc[se.row[r]].add_exact(kGaussWeight[q] * se.thickness, measure[r], weighted[r]);
      }
    }
  }
}

const MasterEdge* Mortar::facing_edge(const std::vector<Vec2>& geo, const MasterEdge& e,
                                      double xi, const std::vector<int>& candidates) const {
  // The nearest master edge that the slave normal ray at xi meets, facing the slave.
  const EdgePoint p = evaluate(e, geo, xi);
  const Vec2 n = outward_normal(p.tangent);
  const MasterEdge* master = nullptr;
  double best = 1e300;
  for (int id : candidates) {
    const MasterEdge& m = master_edges_[id];
    double eta, alpha;
    if (!ray_hit(m, geo, p.x, n, eta, alpha) || eta < -1e-9 || eta > 1 + 1e-9) continue;
    if (std::abs(alpha) > search_ || edge_normal(m, geo, std::clamp(eta, 0.0, 1.0)).dot(n) >= 0)
      continue;
    if (std::abs(alpha) < best) best = std::abs(alpha), master = &m;
  }
  return master;
}

std::vector<std::vector<std::pair<int, double>>> Mortar::coupling(
    const std::vector<Vec2>& reference) const {
  std::vector<Accumulator> acc(corners_.size());
  for (Accumulator& a : acc) a.scalar = true;
  const Configuration c{reference, reference, true};
  const MasterSurfaceSearch search(master_edges_, reference, search_);
  for (const SlaveEdge& se : slave_edges_) integrate_master(c, search, se, acc);
  std::vector<std::vector<std::pair<int, double>>> out;
  for (const Accumulator& a : acc) {
    if (!(a.weight > 0.0)) continue;
    std::vector<std::pair<int, double>> row;
    for (const auto& [node, value] : a.terms)
      if (value.x() != 0.0) row.emplace_back(node, value.x() / a.weight);
    out.push_back(std::move(row));
  }
  return out;
}

void Mortar::detect(const Configuration& c, int first_slot, std::vector<GapRow>& rows) const {
  std::vector<Accumulator> acc(corners_.size());
  if (obstacle_) {
    for (const SlaveEdge& se : slave_edges_) integrate_obstacle(c, se, acc);
  } else {
    const MasterSurfaceSearch search(master_edges_, c.x, search_);
    for (const SlaveEdge& se : slave_edges_) integrate_master(c, search, se, acc);
  }
  for (size_t j = 0; j < acc.size(); ++j) {
    const Accumulator& a = acc[j];
    if (!(a.weight > 0.0)) continue;
    GapRow r;
    r.slave = corners_[j];
    r.gap = a.gap / a.weight;
    r.weight = a.weight;
    r.normal = a.normal.norm() > 0 ? Vec2(a.normal.normalized()) : Vec2(Vec2::UnitY());
    r.terms = a.terms;
    for (auto& t : r.terms) t.second /= a.weight;
    if (!c.small_strain) set_row_derivatives(quotient(a.exact_gap, a.exact_weight), r);
    r.pair = index_;
    r.slot = first_slot + static_cast<int>(j);
    rows.push_back(std::move(r));
  }
}

}  // namespace c2d::constraints
