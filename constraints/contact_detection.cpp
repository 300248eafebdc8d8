#include "constraints/contact_detection.hpp"

#include <algorithm>
#include <cmath>

namespace c2d::constraints {

MasterEdge to_master_edge(const core::BoundaryEdge& be, int order) {
  MasterEdge e;
  e.nodes = be.nodes;
  e.count = order == 1 ? 2 : 3;
  return e;
}

void Obstacle::gap(const Vec2& x, double& g, Vec2& n) const {
  if (type == Type::kLine) {
    n = normal;
    g = normal.dot(x - point);
    return;
  }
  const Vec2 d = x - center;
  const double r = d.norm();
  const Vec2 radial = r > 0 ? Vec2(d / r) : Vec2(Vec2::UnitY());
  if (inside) {
    n = -radial;
    g = radius - r;
  } else {
    n = radial;
    g = r - radius;
  }
}

void edge_shape(int count, double xi, std::array<double, 3>& n, std::array<double, 3>& dn,
                std::array<double, 3>& ddn) {
  if (count == 2) {
    n = {1 - xi, xi, 0};
    dn = {-1, 1, 0};
    ddn = {0, 0, 0};
  } else {
    n = {(1 - xi) * (1 - 2 * xi), xi * (2 * xi - 1), 4 * xi * (1 - xi)};
    dn = {4 * xi - 3, 4 * xi - 1, 4 - 8 * xi};
    ddn = {4, 4, -8};
  }
}

Vec2 combine(const MasterEdge& e, const std::vector<Vec2>& x, const std::array<double, 3>& w) {
  Vec2 out = Vec2::Zero();
  for (int a = 0; a < e.count; ++a) out += w[a] * x[e.nodes[a]];
  return out;
}

Vec2 outward_normal(const Vec2& tangent) {
  const double len = tangent.norm();
  return len > 0 ? Vec2(tangent.y() / len, -tangent.x() / len) : Vec2(0, 0);
}

Vec2 edge_normal(const MasterEdge& e, const std::vector<Vec2>& x, double xi) {
  std::array<double, 3> n, dn, ddn;
  edge_shape(e.count, xi, n, dn, ddn);
  return outward_normal(combine(e, x, dn));
}

SegmentProjection project_on_edge(const MasterEdge& e, const std::vector<Vec2>& x,
                                  const Vec2& p) {
  SegmentProjection out;
  const Vec2 a = x[e.nodes[0]], b = x[e.nodes[1]];
  const double len2 = (b - a).squaredNorm();
  double xi = len2 > 0 ? std::clamp((p - a).dot(b - a) / len2, 0.0, 1.0) : 0.0;
  std::array<double, 3> n, dn, ddn;
  if (e.count == 3) {
    // Newton on d/dxi ½|x(xi) − p|² = (x − p)·x' = 0, kept inside the edge.
    for (int it = 0; it < 30; ++it) {
      edge_shape(3, xi, n, dn, ddn);
      const Vec2 r = combine(e, x, n) - p, t = combine(e, x, dn), tt = combine(e, x, ddn);
      const double f1 = r.dot(t), f2 = t.squaredNorm() + r.dot(tt);
      const double step = f2 > 0 ? -f1 / f2 : 0.0;
      const double next = std::clamp(xi + step, 0.0, 1.0);
      const bool done = std::abs(next - xi) < 1e-14;
      xi = next;
      if (done) break;
    }
  }
  edge_shape(e.count, xi, n, dn, ddn);
  out.found = true;
  out.xi = xi;
  out.point = combine(e, x, n);
  out.normal = outward_normal(combine(e, x, dn));
  out.gap = out.normal.dot(p - out.point);
  out.weights = n;
  return out;
}

MasterSurfaceSearch::MasterSurfaceSearch(std::vector<MasterEdge> edges, const std::vector<Vec2>& x,
                                         double search_distance)
    : edges_(std::move(edges)), x_(x), search_(search_distance) {
  if (edges_.empty()) return;
  Vec2 lo = Vec2::Constant(1e300), hi = Vec2::Constant(-1e300);
  double total = 0.0;
  for (const auto& e : edges_) {
    for (int a = 0; a < e.count; ++a) lo = lo.cwiseMin(x[e.nodes[a]]), hi = hi.cwiseMax(x[e.nodes[a]]);
    total += (x[e.nodes[1]] - x[e.nodes[0]]).norm();
  }
  lo.array() -= search_;
  hi.array() += search_;
  origin_ = lo;
  const Vec2 span = hi - lo;
  cell_ = std::max({total / edges_.size(), search_, 1e-12 * span.norm(), 1e-300});
  nx_ = std::clamp(static_cast<int>(span.x() / cell_) + 1, 1, 4096);
  ny_ = std::clamp(static_cast<int>(span.y() / cell_) + 1, 1, 4096);
  cell_ = std::max({cell_, span.x() / nx_, span.y() / ny_});
  cells_.assign(static_cast<size_t>(nx_) * ny_, {});
  int max_node = 0;
  for (const auto& e : edges_)
    for (int a = 0; a < e.count; ++a) max_node = std::max(max_node, e.nodes[a]);
  vertex_slot_.assign(max_node + 1, -1);
  for (int id = 0; id < static_cast<int>(edges_.size()); ++id) {
    const auto& e = edges_[id];
    Vec2 elo = Vec2::Constant(1e300), ehi = Vec2::Constant(-1e300);
    for (int a = 0; a < e.count; ++a) elo = elo.cwiseMin(x[e.nodes[a]]), ehi = ehi.cwiseMax(x[e.nodes[a]]);
    const int i0 = std::clamp(static_cast<int>((elo.x() - search_ - origin_.x()) / cell_), 0, nx_ - 1);
    const int i1 = std::clamp(static_cast<int>((ehi.x() + search_ - origin_.x()) / cell_), 0, nx_ - 1);
    const int j0 = std::clamp(static_cast<int>((elo.y() - search_ - origin_.y()) / cell_), 0, ny_ - 1);
    const int j1 = std::clamp(static_cast<int>((ehi.y() + search_ - origin_.y()) / cell_), 0, ny_ - 1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) cells_[static_cast<size_t>(j) * nx_ + i].push_back(id);
    for (int end = 0; end < 2; ++end) {
      int& slot = vertex_slot_[e.nodes[end]];
      if (slot < 0) slot = static_cast<int>(vertex_edges_.size()), vertex_edges_.emplace_back();
      vertex_edges_[slot].push_back(id);
    }
  }
}

void MasterSurfaceSearch::cell_range(const Vec2& lo, const Vec2& hi, int& i0, int& i1, int& j0,
                                     int& j1) const {
  i0 = std::clamp(static_cast<int>(std::floor((lo.x() - origin_.x()) / cell_)), 0, nx_ - 1);
  i1 = std::clamp(static_cast<int>(std::floor((hi.x() - origin_.x()) / cell_)), 0, nx_ - 1);
  j0 = std::clamp(static_cast<int>(std::floor((lo.y() - origin_.y()) / cell_)), 0, ny_ - 1);
  j1 = std::clamp(static_cast<int>(std::floor((hi.y() - origin_.y()) / cell_)), 0, ny_ - 1);
}

std::vector<int> MasterSurfaceSearch::edges_near(const Vec2& lo, const Vec2& hi) const {
  std::vector<int> out;
  if (edges_.empty() || hi.x() < origin_.x() || hi.y() < origin_.y() ||
      lo.x() > origin_.x() + nx_ * cell_ || lo.y() > origin_.y() + ny_ * cell_)
    return out;
  int i0, i1, j0, j1;
  cell_range(lo, hi, i0, i1, j0, j1);
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      const auto& cell = cells_[static_cast<size_t>(j) * nx_ + i];
      out.insert(out.end(), cell.begin(), cell.end());
    }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

Vec2 MasterSurfaceSearch::vertex_normal(int node) const {
  Vec2 mean = Vec2::Zero();
  for (int id : vertex_edges_[vertex_slot_[node]]) {
    const auto& e = edges_[id];
    std::array<double, 3> n, dn, ddn;
    edge_shape(e.count, e.nodes[0] == node ? 0.0 : 1.0, n, dn, ddn);
    mean += outward_normal(combine(e, x_, dn));
  }
  return mean.norm() > 0 ? Vec2(mean.normalized()) : mean;
}

bool MasterSurfaceSearch::is_free_end(int node) const {
  return node >= 0 && node < static_cast<int>(vertex_slot_.size()) && vertex_slot_[node] >= 0 &&
         vertex_edges_[vertex_slot_[node]].size() == 1;
}

void MasterSurfaceSearch::treat_vertex(const Vec2& p, SegmentProjection& q) const {
  const MasterEdge& e = edges_[q.edge];
  const int end = q.xi <= 0.0 ? 0 : 1;
  const int node = e.nodes[end];
  const Vec2 d = p - x_[node];
  const Vec2 edge_normal = q.normal;  // the edge's own normal at its end
  q.vertex = node;
  q.point = x_[node];
  q.weights = {0, 0, 0};
  q.weights[end] = 1.0;
  if (is_free_end(node)) {
    // Past a free end the surface continues, for a tenth of the end edge's length, as a
    // parabola tangent to the edge that falls away by that length: a rounded end, so that the
    // gap is continuous (no release of a slave that sank just past the end, no cycling).
    const double band = 0.1 * (x_[e.nodes[1]] - x_[e.nodes[0]]).norm();
    const Vec2 out = (x_[node] - x_[e.nodes[1 - end]]).normalized();  // along the edge, outward
    const double past = out.dot(d);
    if (past <= band) {
      const double s = std::max(past, 0.0);
      q.gap = edge_normal.dot(d) + s * s / band;
      q.branch = SegmentProjection::Branch::kRoundedEnd;
      q.normal = (edge_normal + (2.0 * s / band) * out).normalized();
      return;
    }
    q.beyond_free_end = true;
  }
  const Vec2 mean = vertex_normal(node);
  const bool outside = q.beyond_free_end || mean.dot(d) > 0;
  if (outside && d.norm() > 1e-12 * cell_) {
    q.normal = d.normalized();
    q.gap = d.norm();
    q.branch = SegmentProjection::Branch::kVertexOutside;
  } else {
    q.branch = SegmentProjection::Branch::kVertexInside;
    q.normal = mean.norm() > 0 ? mean : edge_normal;
    q.gap = q.normal.dot(d);
  }
}

SegmentProjection MasterSurfaceSearch::project(const Vec2& p, int exclude_node) const {
  SegmentProjection best;
  if (edges_.empty()) return best;
  const int i = static_cast<int>(std::floor((p.x() - origin_.x()) / cell_));
  const int j = static_cast<int>(std::floor((p.y() - origin_.y()) / cell_));
  if (i < 0 || j < 0 || i >= nx_ || j >= ny_) return best;
  double best_distance = 1e300;
  for (int id : cells_[static_cast<size_t>(j) * nx_ + i]) {
    const auto& e = edges_[id];
    if (std::find(e.nodes.begin(), e.nodes.begin() + e.count, exclude_node) !=
        e.nodes.begin() + e.count)
      continue;
    SegmentProjection q = project_on_edge(e, x_, p);
    const double d = (p - q.point).norm();
    if (d < best_distance - 1e-14 * cell_) {
      best_distance = d;
      best = q;
      best.edge = id;
    }
  }
  if (!best.found) return best;
  // Closest point at an edge end: a vertex shared by edges (sliding across) or a corner.
  if (best.xi <= 0.0 || best.xi >= 1.0) treat_vertex(p, best);
  if (best.gap > search_) best.found = false;
  return best;
}

GapRow node_row(int slave, const Vec2& normal, double gap,
                const std::vector<std::pair<int, double>>& master) {
  GapRow r;
  r.slave = slave;
  r.normal = normal;
  r.gap = gap;
  r.terms.reserve(master.size() + 1);
  r.terms.emplace_back(slave, normal);
  for (const auto& [node, w] : master)
    if (w != 0.0) r.terms.emplace_back(node, -w * normal);
  return r;
}

}  // namespace c2d::constraints
