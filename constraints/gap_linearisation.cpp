#include "constraints/gap_linearisation.hpp"

#include <ceres/jet.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace c2d::constraints {

namespace {

// A gap's derivatives in forward mode: a Jet of Jets over the positions of the nodes it involves
// (value, gradient and Hessian). The Jets are sized to the evaluation: a slave node on a master
// edge (node-to-segment, the common case) involves at most 4 nodes, a master vertex with its two
// edges 6, a mortar point (a quadratic slave edge, a quadratic master edge and two master
// vertices cutting the segment) 8. A Jet of Jets costs the square of its size per operation,
// so sizing it to 4 nodes instead of 8 makes the common row about 3.5× cheaper (Cattaneo-Mindlin:
// 9 % of a frictional run's time in these evaluations before).
template <int kMaxNodes>
struct Jets {
  static constexpr int kN = 2 * kMaxNodes;
  using J1 = ceres::Jet<double, kN>;
  using J2 = ceres::Jet<J1, kN>;
};

/// First-order Jets (value and gradient) for evaluations that need no Hessian.
template <int kMaxNodes>
using FirstOrder = ceres::Jet<double, 2 * kMaxNodes>;

template <class J>
J constant(double v) {
  return J(typename J::Scalar(v));
}

/// Whether J carries value and gradient only (FirstOrder), not the Hessian too (Jets::J2).
template <class J>
constexpr bool kFirstOrder = std::is_same_v<typename J::Scalar, double>;

/// A Jet's value, first or second order.
template <class J>
double value_of(const J& j) {
  if constexpr (kFirstOrder<J>)
    return j.a;
  else
    return j.a.a;
}

template <class J>
struct P {
  J x, y;
};
template <class J>
P<J> operator+(const P<J>& a, const P<J>& b) { return {a.x + b.x, a.y + b.y}; }
template <class J>
P<J> operator-(const P<J>& a, const P<J>& b) { return {a.x - b.x, a.y - b.y}; }
template <class J>
P<J> operator*(const J& s, const P<J>& a) { return {s * a.x, s * a.y}; }
template <class J>
J dot(const P<J>& a, const P<J>& b) { return a.x * b.x + a.y * b.y; }
template <class J>
J norm(const P<J>& a) { return sqrt(dot(a, a)); }
template <class J>
P<J> normalized(const P<J>& a) {
  const J len = norm(a);
  return {a.x / len, a.y / len};
}
/// (t_y, −t_x)/|t|: outward for an edge with its body on the left (as outward_normal).
template <class J>
P<J> outward(const P<J>& t) {
  const J len = norm(t);
  return {t.y / len, -t.x / len};
}

/// The positions of the nodes a gap depends on, as the Jet's variables, relative to the first
/// node's position (the origin).
template <class J>
class Variables {
 public:
  static constexpr int kMaxNodes = J::DIMENSION / 2;
  explicit Variables(const Positions& x) : x_(x) {}
  P<J> at(int node) {
    for (size_t k = 0; k < nodes_.size(); ++k)
      if (nodes_[k] == node) return pos_[k];
    const int k = static_cast<int>(nodes_.size());
    if (k >= kMaxNodes)
      throw std::logic_error("gap linearisation: more than " + std::to_string(kMaxNodes) +
                             " nodes");
    if (k == 0) origin_ = node;
    nodes_.push_back(node);
    const Vec2 v = (x_.reference[node] - x_.reference[origin_]) +
                   (x_.displacement(node) - x_.displacement(origin_));
    if constexpr (kFirstOrder<J>) {
      pos_.push_back({J(v.x(), 2 * k), J(v.y(), 2 * k + 1)});
    } else {
      using J1 = typename J::Scalar;
      pos_.push_back({J(J1(v.x(), 2 * k), 2 * k), J(J1(v.y(), 2 * k + 1), 2 * k + 1)});
    }
    return pos_.back();
  }
  /// A fixed point (an obstacle's) relative to the origin.
  P<J> fixed(const Vec2& point) const {
    const Vec2 v = (point - x_.reference[origin_]) - x_.displacement(origin_);
    return {constant<J>(v.x()), constant<J>(v.y())};
  }
  LocalGap result(const J& g) const {
    LocalGap out;
    out.nodes = nodes_;
    const int n = 2 * static_cast<int>(nodes_.size());
    out.value = value_of(g);
    if constexpr (kFirstOrder<J>) {  // first order: no Hessian
      out.gradient = g.v.head(n);
    } else {
      out.gradient = g.a.v.head(n);
      out.hessian.resize(n, n);
      for (int i = 0; i < n; ++i) out.hessian.row(i) = g.v[i].v.head(n).transpose();
      out.hessian = 0.5 * (out.hessian + out.hessian.transpose()).eval();
    }
    return out;
  }

 private:
  const Positions& x_;
  int origin_ = -1;
  std::vector<int> nodes_;
  std::vector<P<J>> pos_;
};

/// Position, tangent and second derivative of an edge's curve at parameter xi.
template <class J>
struct Curve {
  P<J> x, t, tt;
};

template <class J>
Curve<J> curve(const MasterEdge& e, Variables<J>& v, const J& xi) {
  const J one = constant<J>(1.0), two = constant<J>(2.0), four = constant<J>(4.0);
  J n[3], dn[3], ddn[3];
  if (e.count == 2) {
    n[0] = one - xi, n[1] = xi;
    dn[0] = -one, dn[1] = one;
    ddn[0] = ddn[1] = constant<J>(0.0);
  } else {
    n[0] = (one - xi) * (one - two * xi), n[1] = xi * (two * xi - one),
    n[2] = four * xi * (one - xi);
    dn[0] = four * xi - constant<J>(3.0), dn[1] = four * xi - one,
    dn[2] = four - constant<J>(8.0) * xi;
    ddn[0] = four, ddn[1] = four, ddn[2] = constant<J>(-8.0);
  }
  const P<J> zero{constant<J>(0.0), constant<J>(0.0)};
  Curve<J> c{zero, zero, zero};
  for (int a = 0; a < e.count; ++a) {
    const P<J> xa = v.at(e.nodes[a]);
    c.x = c.x + n[a] * xa;
    c.t = c.t + dn[a] * xa;
    c.tt = c.tt + ddn[a] * xa;
  }
  return c;
}

/// The closest point's parameter on edge e for point p: exact on a straight edge, two Newton
/// steps from the converged xi0 on a curved one.
template <class J>
J closest_parameter(const MasterEdge& e, Variables<J>& v, const P<J>& p, double xi0) {
  if (e.count == 2) {
    const P<J> a = v.at(e.nodes[0]), b = v.at(e.nodes[1]);
    return dot(p - a, b - a) / dot(b - a, b - a);
  }
  J xi = constant<J>(xi0);
  for (int step = 0; step < 2; ++step) {
    const Curve<J> c = curve(e, v, xi);
    const P<J> r = c.x - p;
    xi = xi - dot(r, c.t) / (dot(c.t, c.t) + dot(r, c.tt));
  }
  return xi;
}

/// The parameter where the line through p along unit direction `along`'s normal (the ray
/// p + α n, n ⊥ along) meets edge e: (x(η) − p)·along = 0.
template <class J>
J ray_parameter(const MasterEdge& e, Variables<J>& v, const P<J>& p, const P<J>& along,
                double eta0) {
  if (e.count == 2) {
    const J fa = dot(v.at(e.nodes[0]) - p, along), fb = dot(v.at(e.nodes[1]) - p, along);
    return fa / (fa - fb);
  }
  J eta = constant<J>(eta0);
  for (int step = 0; step < 2; ++step) {
    const Curve<J> c = curve(e, v, eta);
    eta = eta - dot(c.x - p, along) / dot(c.t, along);
  }
  return eta;
}

template <class J>
J obstacle_value(const Obstacle& o, const Variables<J>& v, const P<J>& p) {
  if (o.type == Obstacle::Type::kLine)
    return dot(P<J>{constant<J>(o.normal.x()), constant<J>(o.normal.y())}, p - v.fixed(o.point));
  const J r = norm(p - v.fixed(o.center));
  return o.inside ? constant<J>(o.radius) - r : r - constant<J>(o.radius);
}

/// The gap at a master vertex (the branches of MasterSurfaceSearch::treat_vertex).
template <class J>
J vertex_value(const MasterSurfaceSearch& search, const SegmentProjection& q, Variables<J>& v,
               const P<J>& p) {
  const MasterEdge& e = search.edges()[q.edge];
  const int end = q.xi <= 0.0 ? 0 : 1;
  const P<J> d = p - v.at(e.nodes[end]);
  const P<J> edge_n = outward(curve(e, v, constant<J>(end)).t);
  switch (q.branch) {
    case SegmentProjection::Branch::kRoundedEnd: {
      const J band = constant<J>(0.1) * norm(v.at(e.nodes[1]) - v.at(e.nodes[0]));
      const P<J> out = normalized(v.at(e.nodes[end]) - v.at(e.nodes[1 - end]));
      const J past = dot(out, d);
      return value_of(past) > 0.0 ? dot(edge_n, d) + past * past / band : dot(edge_n, d);
    }
    case SegmentProjection::Branch::kVertexOutside:
      return norm(d);
    default: {
      P<J> mean{constant<J>(0.0), constant<J>(0.0)};
      for (int id : search.vertex_edges(e.nodes[end])) {
        const MasterEdge& a = search.edges()[id];
        mean = mean + outward(curve(a, v, constant<J>(a.nodes[0] == e.nodes[end] ? 0.0 : 1.0)).t);
      }
      return dot(value_of(mean.x) == 0.0 && value_of(mean.y) == 0.0 ? edge_n : normalized(mean), d);
    }
  }
}

/// node_segment_gap with Jets of J's size.
template <class J>
LocalGap node_segment(const MasterSurfaceSearch& search, const SegmentProjection& q, int slave,
                      const Positions& x) {
  Variables<J> v(x);
  const P<J> p = v.at(slave);
  if (q.branch != SegmentProjection::Branch::kEdge) return v.result(vertex_value(search, q, v, p));
  const MasterEdge& e = search.edges()[q.edge];
  const Curve<J> c = curve(e, v, closest_parameter(e, v, p, q.xi));
  return v.result(dot(outward(c.t), p - c.x));
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
                          int slave, const Positions& x, bool hessian) {
  // On an edge's interior or its rounded end: the slave node and the edge (at most 4 nodes);
  // at a vertex: the edges that meet there too.
  const bool one_edge = q.branch == SegmentProjection::Branch::kEdge ||
                        q.branch == SegmentProjection::Branch::kRoundedEnd ||
                        q.branch == SegmentProjection::Branch::kVertexOutside;
  if (!hessian)
    return one_edge ? node_segment<FirstOrder<4>>(search, q, slave, x)
                    : node_segment<FirstOrder<8>>(search, q, slave, x);
  return one_edge ? node_segment<Jets<4>::J2>(search, q, slave, x)
                  : node_segment<Jets<8>::J2>(search, q, slave, x);
}

namespace {
template <class J>
LocalGap obstacle(const Obstacle& obstacle, int slave, const Positions& x) {
  Variables<J> v(x);
  const P<J> p = v.at(slave);
  return v.result(obstacle_value(obstacle, v, p));
}
}  // namespace

LocalGap obstacle_gap(const Obstacle& o, int slave, const Positions& x, bool hessian) {
  return hessian ? obstacle<Jets<1>::J2>(o, slave, x) : obstacle<FirstOrder<1>>(o, slave, x);
}

namespace {

template <class J>
void mortar_point_with(const MasterEdge& slave, SegmentEnd a, SegmentEnd b, double s,
                       const MasterEdge* master, double eta0, const Obstacle* obstacle,
                       const Positions& x, LocalGap measure[2], LocalGap weighted[2]) {
  Variables<J> v(x);
  const auto end = [&](const SegmentEnd& e) {
    return e.vertex < 0 ? constant<J>(e.xi) : closest_parameter(slave, v, v.at(e.vertex), e.xi);
  };
  const J xa = end(a), xb = end(b), xi = xa + (xb - xa) * constant<J>(s);
  const Curve<J> c = curve(slave, v, xi);
  const J jacobian = norm(c.t);
  J g;
  if (master) {
    const P<J> along{c.t.x / jacobian, c.t.y / jacobian};
    const Curve<J> m = curve(*master, v, ray_parameter(*master, v, c.x, along, eta0));
    g = dot(outward(c.t), m.x - c.x);  // the outward normal points at the master
  } else {
    g = obstacle_value(*obstacle, v, c.x);
  }
  const J phi[2] = {constant<J>(1.0) - xi, xi};
  for (int r = 0; r < 2; ++r) {
    const J mr = (xb - xa) * phi[r] * jacobian;
    measure[r] = v.result(mr);
    weighted[r] = v.result(mr * g);
  }
}

/// The distinct nodes a mortar point depends on: the slave edge's, the master edge's and the
/// master vertices that cut the segment.
int mortar_point_nodes(const MasterEdge& slave, SegmentEnd a, SegmentEnd b,
                       const MasterEdge* master) {
  std::array<int, 8> nodes{};
  int n = 0;
  const auto add = [&](int node) {
    if (node >= 0 && std::find(nodes.begin(), nodes.begin() + n, node) == nodes.begin() + n)
      nodes[n++] = node;
  };
  for (int k = 0; k < slave.count; ++k) add(slave.nodes[k]);
  if (master)
    for (int k = 0; k < master->count; ++k) add(master->nodes[k]);
  add(a.vertex);
  add(b.vertex);
  return n;
}

}  // namespace

void mortar_point(const MasterEdge& slave, SegmentEnd a, SegmentEnd b, double s,
                  const MasterEdge* master, double eta0, const Obstacle* obstacle,
                  const Positions& x, LocalGap measure[2], LocalGap weighted[2], bool hessian) {
  // A Jet of Jets costs the square of its size per operation: sized to the point's nodes (a
  // quadratic slave edge on a quadratic master edge whose corners cut the segment: 6, not 8),
  // and first order where only the value and gradient are asked for (a residual).
  if (!hessian) {
    mortar_point_with<FirstOrder<8>>(slave, a, b, s, master, eta0, obstacle, x, measure,
                                     weighted);
    for (int r = 0; r < 2; ++r) {  // zero curvature, in the shape the accumulation expects
      const int n = 2 * static_cast<int>(measure[r].nodes.size());
      measure[r].hessian = Eigen::MatrixXd::Zero(n, n);
      weighted[r].hessian = Eigen::MatrixXd::Zero(n, n);
    }
    return;
  }
  const int nodes = mortar_point_nodes(slave, a, b, master);
  if (nodes <= 4)
    mortar_point_with<Jets<4>::J2>(slave, a, b, s, master, eta0, obstacle, x, measure, weighted);
  else if (nodes <= 6)
    mortar_point_with<Jets<6>::J2>(slave, a, b, s, master, eta0, obstacle, x, measure, weighted);
  else
    mortar_point_with<Jets<8>::J2>(slave, a, b, s, master, eta0, obstacle, x, measure, weighted);
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
