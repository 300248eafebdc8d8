// Mortar segment-to-segment contact: the gap is weighted by multiplier functions Φ_j and
// integrated over the slave surface, g̃_j = ∫ Φ_j g t ds, one row per slave corner node.
//
// Multiplier space: piecewise linear on the slave corner nodes, for T3 and T6 alike. For T6 it
// is the lowest-order stable choice of Wohlmuth, Popp, Gee & Wall (Comput. Mech. 2012): the
// hats are non-negative, so a non-negative gap gives a non-negative weighted gap and a
// non-negative multiplier a non-negative pressure, which the quadratic standard basis does not
// guarantee; the error in the contact pressure stays of the order the solution's regularity
// allows.
//
// Integration (Yang, Laursen & Meng, IJNME 2005): each slave edge is cut where the slave
// normal through a master vertex meets it (the closest-point projection of the vertex onto the
// edge); on each piece the slave-normal ray from a slave point hits one master edge, and a
// 4-point Gauss rule integrates Φ_j N_k and Φ_j N_l(η) exactly for straight edges. Pieces whose
// ray meets no master (past a free end of the master surface) carry no constraint.
//
// In small strain (a linear analysis) the segments, the pairing and the normals are the
// reference configuration's and only the gap values move with u: the linearised Signorini
// problem, whose rows are linear in u.
//
// Rows are divided by their weight w_j = ∫ Φ_j t ds, so a row's gap is a mean gap (a length)
// and its multiplier the force w_j p_j: every enforcement method works on them unchanged, and
// the pressure at node j is λ_j / w_j. A uniform pressure is transmitted exactly (Σ_j Φ_j = 1),
// whether or not the meshes match: the contact patch test.
#pragma once

#include "constraints/discretization.hpp"

namespace c2d::constraints {

class Mortar final : public ContactDiscretization {
 public:
  explicit Mortar(const DiscretizationInput& in);
  int num_slots() const override { return static_cast<int>(corners_.size()); }
  /// Every node of the slave surface (the corner nodes own the rows).
  const std::vector<int>& slave_nodes() const override { return nodes_; }
  void detect(const Configuration& c, int first_slot, std::vector<GapRow>& rows) const override;
  /// A tie's rows in the reference configuration (a deformable master): per slave corner j,
  /// Σ_k D_jk u_k − Σ_l M_jl u_l = 0 with D_jk = ∫ Φ_j N_k ds / w_j over the slave nodes and
  /// M_jl = ∫ Φ_j N_l ds / w_j over the master's, as (node, coefficient) lists. A uniform
  /// traction crosses it exactly on non-matching meshes (Σ_j Φ_j = 1), as for contact.
  std::vector<std::vector<std::pair<int, double>>> coupling(
      const std::vector<Vec2>& reference) const;

  struct SlaveEdge {
    MasterEdge edge;
    double thickness = 1.0;
    int row[2] = {-1, -1};  ///< row index of its end (corner) nodes
  };
  /// A row being integrated.
  struct Accumulator;

 private:
  void integrate_obstacle(const Configuration& c, const SlaveEdge& se,
                          std::vector<Accumulator>& acc) const;
  void integrate_master(const Configuration& c, const MasterSurfaceSearch& search,
                        const SlaveEdge& se, std::vector<Accumulator>& acc) const;
  const MasterEdge* facing_edge(const std::vector<Vec2>& geo, const MasterEdge& e, double xi,
                                const std::vector<int>& candidates) const;

  std::vector<SlaveEdge> slave_edges_;
  std::vector<int> corners_;  ///< row owners, sorted
  std::vector<int> nodes_;    ///< all slave surface nodes, sorted
  std::vector<MasterEdge> master_edges_;
  const Obstacle* obstacle_ = nullptr;
  double search_ = 1e300;
  int index_ = 0;
};

}  // namespace c2d::constraints
