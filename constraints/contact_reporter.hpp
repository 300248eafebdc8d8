// The contact report of a solved state: per slave node its gap, forces, pressure and shear
// (recovered consistently on the slave edges), the totals (active nodes, p_max, the contact and
// stick zones' lengths, the resultant) and the [[constraint]] rows' multipliers and residuals.
#pragma once

#include <map>
#include <vector>

#include "constraints/constrained_problem.hpp"
#include "constraints/constraint_strategy.hpp"
#include "constraints/contact_detection.hpp"
#include "constraints/contact_pairs.hpp"
#include "constraints/contact_report.hpp"
#include "constraints/equality_constraints.hpp"
#include "core/model.hpp"

namespace c2d::constraints {

/// Reports on the contact pairs and equality rows it is built on (it refers to them: they must
/// outlive it); it owns nothing but the penetration limit's factor.
class ContactReporter {
 public:
  ContactReporter(const core::Model& model, const ContactPairs& pairs,
                  const EqualityConstraints& equalities, const StrategyOptions& options);

  /// Fills the per-node results, recovered pressure, p_max, contact length and total force.
  void report(const std::vector<GapRow>& rows, const ConstraintSolution& s, ContactReport& r) const;
  /// The physical limit on a final state's penetration: penetration_limit × the shortest
  /// contact edge (ContactReport::penetration_limit).
  double penetration_limit() const { return penetration_limit_ * pairs_.length_scale(); }

 private:
  /// The [[constraint]] rows' multipliers and residuals.
  void report_equalities(const ConstraintSolution& s, ContactReport& r) const;
  /// The resultant of the rows' forces and its tangential part.
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
  const ContactPairs& pairs_;
  const EqualityConstraints& equalities_;
  double penetration_limit_;  ///< StrategyOptions::penetration_limit (a fraction)
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
