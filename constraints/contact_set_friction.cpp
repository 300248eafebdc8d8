// Friction of the contact pairs: the tangential rows of the gap rows and their laws.
#include <Eigen/Sparse>

#include "constraints/contact_set.hpp"

namespace c2d::constraints {

bool ContactSet::has_friction() const {
  for (const ContactPairSpec& c : spec_.pairs)
    if (c.friction.enabled()) return true;
  return false;
}

void ContactSet::add_tributary() {
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

void ContactSet::add_friction_rows(const std::vector<GapRow>& rows, const VecX& u_full,
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
    if (r.pair >= static_cast<int>(spec_.pairs.size())) continue;  // the seed's gap elements
    const FrictionSpec& f = spec_.pairs[r.pair].friction;
    p.friction_law[i] = f.model;
    p.tangent_penalty_ratio[i] = f.penalty_ratio;
  }
  p.slip_jacobian = SpMat(m, dofs.num_free());
  p.slip_jacobian.setFromTriplets(t.begin(), t.end());
}

}  // namespace c2d::constraints
