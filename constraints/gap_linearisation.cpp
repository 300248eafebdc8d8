#include "constraints/gap_linearisation.hpp"

#include <ceres/jet.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace c2d::constraints {

namespace {

// Up to eight nodes: a slave node and two quadratic master edges meeting at a vertex (6), or a
// quadratic slave edge, a quadratic master edge and two master vertices cutting the segment.
constexpr int kMaxNodes = 8;
constexpr int kN = 2 * kMaxNodes;
using J1 = ceres::Jet<double, kN>;
using J2 = ceres::Jet<J1, kN>;  // value, gradient and Hessian

J2 constant(double v) { return J2(J1(v)); }

struct P {
  J2 x, y;
};
P operator+(const P& a, const P& b) { return {a.x + b.x, a.y + b.y}; }
P operator-(const P& a, const P& b) { return {a.x - b.x, a.y - b.y}; }
P operator*(const J2& s, const P& a) { return {s * a.x, s * a.y}; }
J2 dot(const P& a, const P& b) { return a.x * b.x + a.y * b.y; }
J2 norm(const P& a) { return sqrt(dot(a, a)); }
P normalized(const P& a) {
  const J2 len = norm(a);
  return {a.x / len, a.y / len};
}
/// (t_y, −t_x)/|t|: outward for an edge with its body on the left (as outward_normal).
P outward(const P& t) {
  const J2 len = norm(t);
  return {t.y / len, -t.x / len};
}

/// The positions of the nodes a gap depends on, as the Jet's variables, relative to the first
/// node's position (the origin).
class Variables {
 public:
  explicit Variables(const Positions& x) : x_(x) {}
  P at(int node) {
    for (size_t k = 0; k < nodes_.size(); ++k)
      if (nodes_[k] == node) return pos_[k];
    const int k = static_cast<int>(nodes_.size());
    if (k >= kMaxNodes) throw std::logic_error("gap linearisation: more than 8 nodes");
    if (k == 0) origin_ = node;
    nodes_.push_back(node);
    const Vec2 v = (x_.reference[node] - x_.reference[origin_]) +
                   (x_.displacement(node) - x_.displacement(origin_));
    pos_.push_back({J2(J1(v.x(), 2 * k), 2 * k), J2(J1(v.y(), 2 * k + 1), 2 * k + 1)});
    return pos_.back();
  }
  /// A fixed point (an obstacle's) relative to the origin.
  P fixed(const Vec2& point) const {
    const Vec2 v = (point - x_.reference[origin_]) - x_.displacement(origin_);
    return {constant(v.x()), constant(v.y())};
  }
  LocalGap result(const J2& g) const {
    LocalGap out;
    out.nodes = nodes_;
    const int n = 2 * static_cast<int>(nodes_.size());
    out.value = g.a.a;
    out.gradient = g.a.v.head(n);
    out.hessian.resize(n, n);
    for (int i = 0; i < n; ++i) out.hessian.row(i) = g.v[i].v.head(n).transpose();
    out.hessian = 0.5 * (out.hessian + out.hessian.transpose()).eval();
    return out;
  }

 private:
  const Positions& x_;
  int origin_ = -1;
  std::vector<int> nodes_;
  std::vector<P> pos_;
};

/// Position, tangent and second derivative of an edge's curve at parameter xi.
struct Curve {
  P x, t, tt;
};

Curve curve(const MasterEdge& e, Variables& v, const J2& xi) {
  const J2 one = constant(1.0), two = constant(2.0), four = constant(4.0);
  J2 n[3], dn[3], ddn[3];
  if (e.count == 2) {
    n[0] = one - xi, n[1] = xi;
    dn[0] = -one, dn[1] = one;
    ddn[0] = ddn[1] = constant(0.0);
  } else {
    n[0] = (one - xi) * (one - two * xi), n[1] = xi * (two * xi - one),
    n[2] = four * xi * (one - xi);
    dn[0] = four * xi - constant(3.0), dn[1] = four * xi - one, dn[2] = four - constant(8.0) * xi;
    ddn[0] = four, ddn[1] = four, ddn[2] = constant(-8.0);
  }
  Curve c{{constant(0.0), constant(0.0)}, {constant(0.0), constant(0.0)},
          {constant(0.0), constant(0.0)}};
  for (int a = 0; a < e.count; ++a) {
    const P xa = v.at(e.nodes[a]);
    c.x = c.x + n[a] * xa;
    c.t = c.t + dn[a] * xa;
    c.tt = c.tt + ddn[a] * xa;
  }
  return c;
}

/// The closest point's parameter on edge e for point p: exact on a straight edge, two Newton
/// steps from the converged xi0 on a curved one.
J2 closest_parameter(const MasterEdge& e, Variables& v, const P& p, double xi0) {
  if (e.count == 2) {
    const P a = v.at(e.nodes[0]), b = v.at(e.nodes[1]);
    return dot(p - a, b - a) / dot(b - a, b - a);
  }
  J2 xi = constant(xi0);
  for (int step = 0; step < 2; ++step) {
    const Curve c = curve(e, v, xi);
    const P r = c.x - p;
    xi = xi - dot(r, c.t) / (dot(c.t, c.t) + dot(r, c.tt));
  }
  return xi;
}

/// The parameter where the line through p along unit direction `along`'s normal (the ray
/// p + α n, n ⊥ along) meets edge e: (x(η) − p)·along = 0.
J2 ray_parameter(const MasterEdge& e, Variables& v, const P& p, const P& along, double eta0) {
  if (e.count == 2) {
    const J2 fa = dot(v.at(e.nodes[0]) - p, along), fb = dot(v.at(e.nodes[1]) - p, along);
    return fa / (fa - fb);
  }
  J2 eta = constant(eta0);
  for (int step = 0; step < 2; ++step) {
    const Curve c = curve(e, v, eta);
    eta = eta - dot(c.x - p, along) / dot(c.t, along);
  }
  return eta;
}

J2 obstacle_value(const Obstacle& o, const Variables& v, const P& p) {
  if (o.type == Obstacle::Type::kLine)
    return dot(P{constant(o.normal.x()), constant(o.normal.y())}, p - v.fixed(o.point));
  const J2 r = norm(p - v.fixed(o.center));
  return o.inside ? constant(o.radius) - r : r - constant(o.radius);
}

/// The gap at a master vertex (the branches of MasterSurfaceSearch::treat_vertex).
J2 vertex_value(const MasterSurfaceSearch& search, const SegmentProjection& q, Variables& v,
                const P& p) {
  const MasterEdge& e = search.edges()[q.edge];
  const int end = q.xi <= 0.0 ? 0 : 1;
  const P d = p - v.at(e.nodes[end]);
  const P edge_n = outward(curve(e, v, constant(end)).t);
  switch (q.branch) {
    case SegmentProjection::Branch::kRoundedEnd: {
      const J2 band = constant(0.1) * norm(v.at(e.nodes[1]) - v.at(e.nodes[0]));
      const P out = normalized(v.at(e.nodes[end]) - v.at(e.nodes[1 - end]));
      const J2 past = dot(out, d);
      return past.a.a > 0.0 ? dot(edge_n, d) + past * past / band : dot(edge_n, d);
    }
    case SegmentProjection::Branch::kVertexOutside:
      return norm(d);
    default: {
      P mean{constant(0.0), constant(0.0)};
      for (int id : search.vertex_edges(e.nodes[end])) {
        const MasterEdge& a = search.edges()[id];
        mean = mean + outward(curve(a, v, constant(a.nodes[0] == e.nodes[end] ? 0.0 : 1.0)).t);
      }
      return dot(mean.x.a.a == 0.0 && mean.y.a.a == 0.0 ? edge_n : normalized(mean), d);
    }
  }
}

}  // namespace

int LocalGap::slot(int node) {
  for (size_t k = 0; k < nodes.size(); ++k)
    if (nodes[k] == node) return static_cast<int>(k);
  nodes.push_back(node);
  const int n = 2 * static_cast<int>(nodes.size());
  gradient.conservativeResize(n);
  gradient.tail(2).setZero();
  hessian.conservativeResize(n, n);
  hessian.rightCols(2).setZero();
  hessian.bottomRows(2).setZero();
  return n / 2 - 1;
}

void LocalGap::add(double scale, const LocalGap& other) {
  value += scale * other.value;
  std::vector<int> at(other.nodes.size());
  for (size_t k = 0; k < other.nodes.size(); ++k) at[k] = slot(other.nodes[k]);
  for (size_t i = 0; i < at.size(); ++i) {
    gradient.segment<2>(2 * at[i]) += scale * other.gradient.segment<2>(2 * i);
    for (size_t j = 0; j < at.size(); ++j)
      hessian.block<2, 2>(2 * at[i], 2 * at[j]) += scale * other.hessian.block<2, 2>(2 * i, 2 * j);
  }
}

LocalGap node_segment_gap(const MasterSurfaceSearch& search, const SegmentProjection& q,
                          int slave, const Positions& x) {
  Variables v(x);
  const P p = v.at(slave);
  if (q.branch != SegmentProjection::Branch::kEdge) return v.result(vertex_value(search, q, v, p));
  const MasterEdge& e = search.edges()[q.edge];
  const Curve c = curve(e, v, closest_parameter(e, v, p, q.xi));
  return v.result(dot(outward(c.t), p - c.x));
}

LocalGap obstacle_gap(const Obstacle& obstacle, int slave, const Positions& x) {
  Variables v(x);
  const P p = v.at(slave);
  return v.result(obstacle_value(obstacle, v, p));
}

void mortar_point(const MasterEdge& slave, SegmentEnd a, SegmentEnd b, double s,
                  const MasterEdge* master, double eta0, const Obstacle* obstacle,
                  const Positions& x, LocalGap measure[2], LocalGap weighted[2]) {
  Variables v(x);
  const auto end = [&](const SegmentEnd& e) {
    return e.vertex < 0 ? constant(e.xi) : closest_parameter(slave, v, v.at(e.vertex), e.xi);
  };
  const J2 xa = end(a), xb = end(b), xi = xa + (xb - xa) * constant(s);
  const Curve c = curve(slave, v, xi);
  const J2 jacobian = norm(c.t);
  J2 g;
  if (master) {
    const P along{c.t.x / jacobian, c.t.y / jacobian};
    const Curve m = curve(*master, v, ray_parameter(*master, v, c.x, along, eta0));
    g = dot(outward(c.t), m.x - c.x);  // the outward normal points at the master
  } else {
    g = obstacle_value(*obstacle, v, c.x);
  }
  const J2 phi[2] = {constant(1.0) - xi, xi};
  for (int r = 0; r < 2; ++r) {
    const J2 mr = (xb - xa) * phi[r] * jacobian;
    measure[r] = v.result(mr);
    weighted[r] = v.result(mr * g);
  }
}

LocalGap quotient(const LocalGap& a, const LocalGap& w) {
  // g = a / w:  ∇g = (∇a − g ∇w) / w,  ∇²g = (∇²a − g ∇²w − ∇g ∇wᵀ − ∇w ∇gᵀ) / w.
  LocalGap out, den;  // both on the union of the node lists, in one order
  out.add(1.0, a);
  out.add(0.0, w);
  den.add(0.0, out);
  den.add(1.0, w);
  const double wv = w.value;
  out.value = a.value / wv;
  out.gradient = (out.gradient - out.value * den.gradient) / wv;
  out.hessian = (out.hessian - out.value * den.hessian - out.gradient * den.gradient.transpose() -
                 den.gradient * out.gradient.transpose()) /
                wv;
  return out;
}

void set_row_derivatives(const LocalGap& g, GapRow& row) {
  row.gap = g.value;
  row.terms.clear();
  for (size_t k = 0; k < g.nodes.size(); ++k)
    row.terms.emplace_back(g.nodes[k], Vec2(g.gradient.segment<2>(2 * k)));
  row.curvature = g.hessian;
}

}  // namespace c2d::constraints
