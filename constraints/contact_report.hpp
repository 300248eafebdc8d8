// What a solve reports about its contacts and equality rows: per slave node its gap, forces,
// pressure and friction state, per equality row its multiplier, per plate its motion and force,
// and the totals (ContactReporter fills it, EqualityConstraints its plates).
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "constraints/constrained_problem.hpp"
#include "core/types.hpp"

namespace c2d::constraints {

/// Per slave node, after a solve.
struct ContactNodeResult {
  int node = -1;
  Vec2 x = Vec2::Zero();  ///< reference position
  double gap = 0.0;       ///< smallest gap of its rows (negative = penetration)
  double force = 0.0;     ///< normal contact force (≥ 0)
  double pressure = 0.0;  ///< recovered contact pressure (0 for nodes on no slave edge)
  double penalty = 0.0;   ///< penalty stiffness used (penalty-type methods)
  bool active = false;
  /// Friction: the tangential force on the slave along t (the normal turned clockwise; −λ_t),
  /// the shear traction recovered from it like the pressure, the slip of the step along t, and
  /// the state.
  double tangent_force = 0.0;
  double shear = 0.0;
  double slip = 0.0;
  double accumulated_slip = 0.0;  ///< Σ |slip| over the steps (a load-stepped run sums them)
  FrictionState state = FrictionState::kOpen;
};

/// Per equality row after a solve: the force its multiplier exerts and what is left of it.
struct EqualityRowResult {
  int owner = -1;
  double multiplier = 0.0;  ///< μ: the row's force on the structure is Aᵀμ
  double residual = 0.0;    ///< A u − b
};

/// A rigid plate after a solve: its motion and the force it transmits to the structure.
struct PlateResult {
  std::string name;
  Vec2 u = Vec2::Zero();      ///< translation of the reference point
  double rotation = 0.0;      ///< θ, radians
  Vec2 force = Vec2::Zero();  ///< resultant the plate exerts on the structure
  double moment = 0.0;        ///< its moment about the reference point
};

struct ContactReport {
  std::string method;
  /// Load steps the method's fallback finished (ConstraintStrategy::fallback), its name, and
  /// why the last one was handed over ("its sets cycled", or the method's reason).
  int fallback_steps = 0;
  std::string fallback_method;
  std::string fallback_reason;
  SolveStatus status = SolveStatus::kFailed;
  std::string message;
  int iterations = 0;  ///< backend iterations summed over detection passes
  int detection_passes = 0;
  int rows = 0;  ///< gap rows in the last pass
  std::vector<ContactNodeResult> nodes;
  int active_nodes = 0;
  double p_max = 0.0;
  double length = 0.0;           ///< measure of the slave surface carrying pressure
  double max_penetration = 0.0;  ///< of the solved (linearised) rows
  /// Of the rows detected afresh at the final positions, and the bound a converged run keeps
  /// it under (the method's own penetration + 1e-9 × model size); NaN when not measured.
  double measured_penetration = std::numeric_limits<double>::quiet_NaN();
  double penetration_tolerance = std::numeric_limits<double>::quiet_NaN();
  /// The deepest slave node below the master surface at the final positions (see
  /// ContactPairs::nodal_penetration); NaN when not measured.
  double nodal_penetration = std::numeric_limits<double>::quiet_NaN();
  /// The physical limit: penetration_limit × the shortest contact edge (StrategyOptions).
  double penetration_limit = std::numeric_limits<double>::quiet_NaN();
  double total_force = 0.0;        ///< Σ normal forces
  double seconds = 0.0;            ///< time in the backend
  double detection_seconds = 0.0;  ///< time in contact search (every detection pass)
  double pivot_ratio = std::numeric_limits<double>::quiet_NaN();    ///< of the last solve
  double stiffness_max = std::numeric_limits<double>::quiet_NaN();  ///< max |K_ij| (linear runs)
  bool has_surface = false;  ///< pressures recovered on slave edges
  bool friction = false;     ///< some pair has friction: the nodes' tangential fields are set
  int stick_nodes = 0, slip_nodes = 0;
  /// The tangential part of the resultant: `resultant` along the slave surface's mean tangent
  /// in the reference configuration (its normals into the slave weighted by the rows' forces,
  /// normalised, turned clockwise); the frame the loads of a contact problem are stated in. A
  /// sum of the nodes' tangential forces, each along its own deformed tangent, is not a force
  /// of the body: on Cattaneo–Mindlin (finite strain) it read 150.08 for the cap's 150.
  double tangent_force = 0.0;
  /// The resultant of the contact forces on the slave surface, normal and friction: Σ (λ n + q t).
  Vec2 resultant = Vec2::Zero();
  double stick_length = 0.0;  ///< measure of the slave surface owned by sticking nodes
  std::vector<EqualityRowResult> equalities;                ///< the [[constraint]] rows
  std::vector<std::string> equality_names, equality_types;  ///< per [[constraint]]
  double max_equality_violation = 0.0;                      ///< max |A u − b| over them
  std::vector<PlateResult> plates;                          ///< the [[plate]]s
  std::vector<IterationRecord> history;
  std::vector<double> penalty_history;
};

}  // namespace c2d::constraints
