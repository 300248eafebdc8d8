#include "constraints/equalities/rigid_plate.hpp"

#include <cmath>

namespace c2d::constraints {

namespace {

/// The quarter turn J v.
Vec2 quarter(const Vec2& v) { return Vec2(-v.y(), v.x()); }

/// A row c(u) from its value and gradient at u: terms = ∇c, rhs = ∇c·u − c.
EqualityRow linearised(std::vector<std::pair<int, double>> terms, double value, const VecX& u,
                       int owner) {
  EqualityRow row;
  row.owner = owner;
  row.rhs = -value;
  for (const auto& [dof, a] : terms) row.rhs += a * u[dof];
  row.terms = std::move(terms);
  return row;
}

void add_curvature(EqualityRow& row, int a, int b, double value) {
  if (value == 0.0) return;
  row.curvature.emplace_back(a, b, value);
  if (a != b) row.curvature.emplace_back(b, a, value);
}

}  // namespace

void rigid_plate_rows(const core::Model& model, int p, const VecX& u, bool small_strain,
                      std::vector<EqualityRow>& out) {
  const core::RigidPlate& plate = model.plates[p];
  const int q = plate.dof, owner = -1 - p;
  const Vec2 U = u.segment<2>(q);
  const double theta = small_strain ? 0.0 : u[q + 2];
  const double c = std::cos(theta), s = std::sin(theta);
  for (int node : plate.nodes) {
    const Vec2 r = model.mesh.nodes[node] - plate.reference;
    const Vec2 ui = u.segment<2>(2 * node);
    if (plate.normal_only) {
      // c = n(θ)·d − n₀·r, d = r + u_i − U; ∂c/∂θ = (J n)·d, ∂²c/∂θ² = −n·d.
      const Vec2 n(c * plate.normal.x() - s * plate.normal.y(),
                   s * plate.normal.x() + c * plate.normal.y());
      const Vec2 jn = quarter(n);
      const Vec2 d = small_strain ? r : Vec2(r + ui - U);
      const double value = small_strain ? n.dot(ui - U) + u[q + 2] * jn.dot(r)
                                        : n.dot(d) - plate.normal.dot(r);
      EqualityRow row = linearised({{2 * node, n.x()}, {2 * node + 1, n.y()}, {q, -n.x()},
                                    {q + 1, -n.y()}, {q + 2, jn.dot(d)}},
                                   value, u, owner);
      if (!small_strain) {
        add_curvature(row, q + 2, q + 2, -n.dot(d));
        for (int k = 0; k < 2; ++k) {
          add_curvature(row, q + 2, 2 * node + k, jn[k]);
          add_curvature(row, q + 2, q + k, -jn[k]);
        }
      }
      out.push_back(std::move(row));
      continue;
    }
    // c = u_i − U − (R(θ) − I) r; ∂c/∂θ = −R' r = −J R r, ∂²c/∂θ² = R r.
    const Vec2 rr(c * r.x() - s * r.y(), s * r.x() + c * r.y());
    const Vec2 turn = small_strain ? Vec2(u[q + 2] * quarter(r)) : Vec2(rr - r);
    const Vec2 dtheta = small_strain ? Vec2(-quarter(r)) : Vec2(-quarter(rr));
    for (int k = 0; k < 2; ++k) {
      EqualityRow row = linearised({{2 * node + k, 1.0}, {q + k, -1.0}, {q + 2, dtheta[k]}},
                                   ui[k] - U[k] - turn[k], u, owner);
      if (!small_strain) add_curvature(row, q + 2, q + 2, rr[k]);
      out.push_back(std::move(row));
    }
  }
}

}  // namespace c2d::constraints
