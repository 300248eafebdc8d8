// Exact linearisation of contact gaps in the current configuration (finite strain).
//
// A row's gap is a function of the positions of the few nodes it involves: the slave node and
// the master edge it projects on (node-to-segment), or a slave edge and the master edge its
// normal rays hit (a mortar quadrature point). Newton needs the gap, its gradient (the row of
// G) and its Hessian (the row force λ turns it into the contact's geometric stiffness −λ ∂²g):
// without the Hessian, a sliding contact's normal turns between iterations and Newton falls to
// linear convergence. All three come from one templated evaluation of the gap in forward-mode
// automatic differentiation with ceres::Jet nested in itself, so the derivatives are those of
// the very function detection evaluates, every branch included (edge interior, rounded free
// end, vertex outside and inside).
//
// A closest-point or ray parameter ξ(x) is implicit. It enters through two Newton steps taken
// in Jet arithmetic from its converged value: one step carries its first derivatives exactly,
// the second its second derivatives (each step squares the error of the derivatives).
#pragma once

#include <vector>

#include "constraints/contact_detection.hpp"
#include "core/types.hpp"

namespace c2d::constraints {

/// Node positions X + u with the displacement kept apart: a gap is evaluated from positions
/// relative to its first node, formed as (X_a − X_o) + (u_a − u_o), which keeps u's digits where
/// X + u would round them off to ε|X| (a penalty k turns that into a force noise k ε |X|).
struct Positions {
  const std::vector<Vec2>& reference;
  const VecX* u = nullptr;  ///< 2 per node; null: `reference` are the positions
  Vec2 displacement(int node) const { return u ? Vec2(u->segment<2>(2 * node)) : Vec2::Zero(); }
};

/// A scalar function of node positions with its exact gradient and Hessian.
struct LocalGap {
  std::vector<int> nodes;  ///< the nodes it depends on (distinct)
  double value = 0.0;
  VecX gradient;           ///< 2 per node, in `nodes` order: ∂g/∂x_node
  Eigen::MatrixXd hessian; ///< 2n × 2n, same order

  /// Adds scale × other, merging the node lists.
  void add(double scale, const LocalGap& other);
  /// The node's position in `nodes`, appended (with zero derivatives) when new.
  int slot(int node);
};

/// The node-to-segment gap of slave node `slave` at positions x, on the branch the search chose
/// for its projection q (q from search.project(x[slave])).
/// Without `hessian`, the value and gradient only (first-order Jets; `hessian` left empty): what
/// a residual needs, at a ninth of the cost.
LocalGap node_segment_gap(const MasterSurfaceSearch& search, const SegmentProjection& q,
                          int slave, const Positions& x, bool hessian = true);

/// The gap of slave node `slave` against an analytic obstacle.
LocalGap obstacle_gap(const Obstacle& obstacle, int slave, const Positions& x,
                      bool hessian = true);

/// An end of a mortar segment on a slave edge: a fixed parameter (an end of the edge), or
/// where the slave normal passes master node `vertex` (its closest point on the slave edge;
/// xi: the converged value), which moves with the positions.
struct SegmentEnd {
  double xi = 0.0;
  int vertex = -1;
};

/// A mortar quadrature point at s ∈ [0, 1] of the segment [a, b] of slave edge `slave`, for the
/// two corner hats Φ_0 = 1 − ξ, Φ_1 = ξ: measure[r] = (b − a) Φ_r(ξ) |dx/dξ| and weighted[r] =
/// measure[r] · g, with g the gap along the slave normal to the master edge's curve at the
/// ray's parameter (eta0: its converged value) or, without a master, to the obstacle. The
/// segment's ends move with the positions, so the quadrature is differentiated as it is.
/// Without `hessian`, the value and gradient only (the Hessians zero): what a residual needs.
void mortar_point(const MasterEdge& slave, SegmentEnd a, SegmentEnd b, double s,
                  const MasterEdge* master, double eta0, const Obstacle* obstacle,
                  const Positions& x, LocalGap measure[2], LocalGap weighted[2],
                  bool hessian = true);

/// a / w with its exact derivatives (a mortar row: the weighted gap over the row's weight).
LocalGap quotient(const LocalGap& a, const LocalGap& w);

/// The row of a local gap: its value, terms = the gradient per node, curvature = the Hessian.
void set_row_derivatives(const LocalGap& g, GapRow& row);

}  // namespace c2d::constraints
