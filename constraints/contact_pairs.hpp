// The contact pairs of a model: one discretization per [[contact]] (and the seed's gap elements
// of a legacy scene as one node_to_node pair after them), the gap rows they detect at any
// configuration, the rows' Jacobian and curvature, and the normal and tangential rows of the
// constrained problem.
#pragma once

#include <memory>
#include <vector>

#include "constraints/constrained_problem.hpp"
#include "constraints/contact_detection.hpp"
#include "constraints/contact_scene.hpp"
#include "constraints/discretization.hpp"
#include "core/model.hpp"

namespace c2d::constraints {

/// Owns the pairs' discretizations, their gauges and slots, the slave nodes and edges with each
/// node's tributary area, and the master surfaces' reference normals.
class ContactPairs {
 public:
  /// Resolves the selections of `spec`'s [[contact]] tables on the model (throws InputError when
  /// one matches nothing) and adds the seed's gap elements of a legacy scene.
  ContactPairs(const core::Model& model, const ContactSceneSpec& spec, const core::Scene& scene);

  bool empty() const { return pairs_.empty(); }
  int num_slave_nodes() const { return static_cast<int>(slave_nodes_.size()); }

  /// Gap rows at the configuration X + u (u: full displacement vector); `small_strain` takes
  /// normals and measures from the reference configuration (see Configuration).
  /// Without `curvature`, finite-strain rows carry their values and gradients only.
  std::vector<GapRow> detect(const VecX& u_full, bool small_strain = false,
                             bool curvature = true) const;
  /// The deepest slave node below its master surface at the configuration X + u: each slave
  /// node projected onto the current master surface (quadratic edges on T6), whatever the
  /// pair's discretization (a mortar row's weighted gap allows a node an overlap of the
  /// order h²/R between its neighbours). 0 when none penetrates.
  double nodal_penetration(const VecX& u_full) const;

  /// The rows' gradients on the free DOFs: G, m × n_free (prescribed DOFs dropped).
  SpMat gap_jacobian(const std::vector<GapRow>& rows) const;
  /// The contact's geometric stiffness on the free DOFs, −Σ_i λ_i ∂²g_i/∂u², from the rows'
  /// curvature and their forces λ (n_free × n_free; zero for rows linear in u).
  SpMat geometric_stiffness(const std::vector<GapRow>& rows, const VecX& force) const;

  /// The rows linearised about u_full (the detection configuration) into `p` (see
  /// ConstrainedProblem), with prescribed DOFs moved into g0, and each row's areas.
  void add_gap_rows(const std::vector<GapRow>& rows, const VecX& u_full,
                    ConstrainedProblem& p) const;
  /// Whether some [[contact]] has friction.
  bool has_friction() const;
  /// The tangential rows of `rows` and their friction laws into `p` (see ConstrainedProblem):
  /// the slip from `u_reference` (the last converged full displacement; null: the undeformed
  /// state) to u_full.
  void add_friction_rows(const std::vector<GapRow>& rows, const VecX& u_full,
                         const VecX* u_reference, ConstrainedProblem& p) const;

  /// Each (contact entry, slave node) combination and each node pair has a slot, the stable
  /// identity of its row across detections (GapRow::slot): active sets and multipliers carried
  /// from one detection, iteration or load step to the next are indexed by it.
  int num_slots() const { return num_slots_; }
  /// Smallest slave (else master) edge length: the scale of relative tolerances.
  double length_scale() const { return length_scale_; }

  /// The slave nodes of every pair: unique, sorted.
  const std::vector<int>& slave_nodes() const { return slave_nodes_; }
  /// The slave surfaces (for pressure recovery) and each edge's thickness.
  const std::vector<MasterEdge>& slave_edges() const { return slave_edges_; }
  const std::vector<double>& slave_edge_thickness() const { return slave_edge_thickness_; }
  /// Per node: the unit mean of its master edges' normals out of the body, weighted by the
  /// edges' lengths (reference configuration; zero off the master surfaces): the frame of the
  /// tangential force.
  const std::vector<Vec2>& master_outward() const { return master_outward_; }

 private:
  /// The slave surface of one [[contact]] (for pressure recovery); a selection without boundary
  /// edges is refused when `required` (the discretization recovers pressure on the surface).
  void add_slave_edges(const ContactPairSpec& cs, bool required);
  /// Adds the master surface's reference normals (out of the master body, toward the slave) of
  /// a pair with a deformable master to master_outward_, each as long as its edge (the
  /// constructor makes the sums unit vectors once every pair is in).
  void add_master_normals(const ContactPairSpec& cs);
  /// The rows at X + u of every pair, or of its gauge where it has one (`gauges`).
  std::vector<GapRow> detect_with(const VecX& u_full, bool small_strain, bool curvature,
                                  bool gauges) const;
  /// Each slave node's share of the slave surface (tributary_).
  void add_tributary();
  /// The seed's gap elements of a legacy model, as one node_to_node pair after the scene's.
  void add_gap_elements(const core::ExplicitModel& legacy);

  const core::Model& model_;
  std::vector<ContactPairSpec> specs_;  ///< the [[contact]] tables
  std::vector<Obstacle> obstacles_;     ///< the scene's, which the discretizations point into
  std::vector<std::unique_ptr<ContactDiscretization>> pairs_;  ///< one per [[contact]] (+ gaps)
  /// Per [[contact]] whose rows are not one per slave node: a node_to_segment of the same
  /// surfaces, the gauge of nodal_penetration (null: the pair is its own gauge).
  std::vector<std::unique_ptr<ContactDiscretization>> gauges_;
  std::vector<int> first_slot_;          ///< per pair: the slot of its first row
  std::vector<int> slave_nodes_;         ///< unique, sorted
  std::vector<MasterEdge> slave_edges_;  ///< slave surface, for pressure recovery
  std::vector<double> slave_edge_thickness_;
  std::vector<double> tributary_;     ///< per node: ∫ N ds t over the slave edges
  std::vector<Vec2> master_outward_;  ///< see master_outward()
  double length_scale_ = 1.0;
  int num_slots_ = 0;
};

/// The straight distance between a master or slave edge's end nodes.
double chord(const std::vector<Vec2>& x, const MasterEdge& e);

}  // namespace c2d::constraints
