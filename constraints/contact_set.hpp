// The contact pairs of a model: detection at any configuration, the constrained problem the
// strategies solve, and the report (gaps, forces, a consistently recovered pressure).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "constraints/constrained_problem.hpp"
#include "constraints/contact_detection.hpp"
#include "constraints/contact_pairs.hpp"
#include "constraints/contact_report.hpp"
#include "constraints/contact_scene.hpp"
#include "constraints/discretization.hpp"
#include "constraints/equality_constraints.hpp"
#include "core/dof_map.hpp"
#include "core/model.hpp"

namespace c2d::constraints {

class ContactSet {
 public:
  /// Resolves the selections of `spec` on the model (throws InputError when one matches nothing)
  /// and adds the seed's gap elements of a legacy scene.
  ContactSet(const core::Model& model, const ContactSceneSpec& spec, const core::Scene& scene);

  bool empty() const { return pairs_.empty() && equalities_.empty(); }
  const ContactPairs& pairs() const { return pairs_; }
  const EqualityConstraints& equalities() const { return equalities_; }
  const StrategyOptions& options() const { return options_; }
  /// The equality rows' (EqualityConstraints).
  const std::vector<EqualityRow>& equality_rows() const { return equalities_.constraint_rows(); }
  std::vector<EqualityRow> equality_rows_at(const VecX& u_full, bool small_strain) const {
    return equalities_.rows_at(u_full, small_strain);
  }
  bool has_nonlinear_equalities() const { return equalities_.has_nonlinear_rows(); }
  SpMat equality_jacobian(const std::vector<EqualityRow>& rows) const {
    return equalities_.jacobian(rows);
  }
  VecX equality_values(const std::vector<EqualityRow>& rows, const VecX& u_full) const {
    return equalities_.values(rows, u_full);
  }
  SpMat equality_geometric_stiffness(const std::vector<EqualityRow>& rows, const VecX& mu) const {
    return equalities_.geometric_stiffness(rows, mu);
  }
  void report_plates(const VecX& u_full, const VecX& mu, bool small_strain,
                     ContactReport& r) const {
    equalities_.report_plates(u_full, mu, small_strain, r);
  }
  int num_slave_nodes() const { return pairs_.num_slave_nodes(); }

  /// The contact pairs' (ContactPairs).
  std::vector<GapRow> detect(const VecX& u_full, bool small_strain = false,
                             bool curvature = true) const {
    return pairs_.detect(u_full, small_strain, curvature);
  }
  double nodal_penetration(const VecX& u_full) const { return pairs_.nodal_penetration(u_full); }

  /// The problem on the free DOFs: K, f, and the rows linearised about u_full (the detection
  /// configuration), with prescribed DOFs moved into g0.
  /// With friction, the tangential rows too: the slip from `u_reference` (the last converged
  /// full displacement; null: the undeformed state) to u.
  ConstrainedProblem problem(const SpMat& k_ff, const VecX& f_ff, const std::vector<GapRow>& rows,
                             const VecX& u_full, bool small_strain = true,
                             const VecX* u_reference = nullptr) const;
  /// The contact pairs' (ContactPairs).
  bool has_friction() const { return pairs_.has_friction(); }
  SpMat gap_jacobian(const std::vector<GapRow>& rows) const { return pairs_.gap_jacobian(rows); }
  SpMat geometric_stiffness(const std::vector<GapRow>& rows, const VecX& force) const {
    return pairs_.geometric_stiffness(rows, force);
  }

  /// Fills the per-node results, recovered pressure, p_max, contact length and total force.
  void report(const std::vector<GapRow>& rows, const ConstraintSolution& s, ContactReport& r) const;

  /// The contact pairs' (ContactPairs).
  int num_slots() const { return pairs_.num_slots(); }
  double length_scale() const { return pairs_.length_scale(); }
  double model_size() const { return model_.model_size; }

 private:
  /// The [[constraint]] rows' multipliers and residuals (contact_set_report.cpp).
  void report_equalities(const ConstraintSolution& s, ContactReport& r) const;
  /// The resultant of the rows' forces and its tangential part (contact_set_report.cpp).
  void add_resultant(const std::vector<GapRow>& rows, const ConstraintSolution& s,
                     ContactReport& r) const;
  /// Pressures of the report's nodes (`slot`: node → index): λ / w on mortar rows, recovered
  /// from the nodal forces elsewhere.
  /// Edges of `side_edge` are left out (side_edges).
  void assign_pressure(const std::map<int, int>& slot, const std::vector<double>& mortar_weight,
                       const std::vector<char>& mortar_edge, const std::vector<char>& side_edge,
                       ContactReport& r) const;
  /// Per slave edge: whether it is a side of the body beside the contact zone, not part of the
  /// contact surface (one end active, its outward normal turned more than 45 degrees from facing
  /// the master there); `contact_normal` per report node, the active row's normal (else zero).
  std::vector<char> side_edges(const std::map<int, int>& slot,
                               const std::vector<Vec2>& contact_normal,
                               const std::vector<ContactNodeResult>& nodes) const;
  /// The length of the longest run of sticking nodes along the slave surface (the stick zone),
  /// each node counting what it owns (`owned`, per report node).
  double stick_zone_length(const std::map<int, int>& slot, const std::vector<char>& side_edge,
                           const std::vector<ContactNodeResult>& sticking,
                           const std::vector<double>& owned) const;
  /// Per report node (`slot`), the arc length of the slave surface it owns (side edges left
  /// out): the contact length is the sum over active nodes.
  std::vector<double> owned_lengths(const std::map<int, int>& slot,
                                    const std::vector<char>& mortar_edge,
                                    const std::vector<char>& side_edge) const;

  const core::Model& model_;
  StrategyOptions options_;
  ContactPairs pairs_;
  EqualityConstraints equalities_;
};

/// Consistent recovery of a pressure field from nodal normal forces on a line of boundary
/// edges: solves M p = f with the edge mass matrix M = Σ t ∫ N_a N_b ds, so a pressure the
/// discretisation can represent comes back exactly (a quadratic edge's 1 : 4 : 1 nodal forces do
/// not turn into oscillating corner and mid-side values, as dividing by a tributary length does).
/// Only the active nodes carry unknowns; the others hold p = 0, which confines the projection's
/// ringing at the edge of the contact zone (where the Hertz pressure has a square-root
/// singularity in its slope). Returns one value per entry of `nodes`.
VecX recover_pressure(const std::vector<Vec2>& x, const std::vector<MasterEdge>& edges,
                      const std::vector<double>& thickness, const std::vector<int>& nodes,
                      const VecX& force, const std::vector<char>& active);

}  // namespace c2d::constraints
