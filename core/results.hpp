// What one analysis produces.
#pragma once

#include <map>
#include <string>

#include "core/error_estimator.hpp"
#include "core/solver_status.hpp"
#include "core/spd_solver.hpp"
#include "core/stress_recovery.hpp"
#include "core/types.hpp"

namespace c2d::core {

struct PhaseTimes {
  double mesh = 0, assemble = 0, solve = 0, recovery = 0, output = 0, total = 0;
};

struct Results {
  SolveStatus status = SolveStatus::kFailed;
  std::string message;         ///< why it failed; empty on success
  VecX displacement;           ///< full, 2 per node
  VecX reaction;               ///< full: f_int - f_ext on constrained DOFs, 0 elsewhere
  ElementStresses element_stresses;
  Eigen::Matrix3Xd nodal_stress;  ///< smoothed, 3 x nodes
  ErrorEstimate error;
  SpdSolveReport solver;
  PhaseTimes time;
  std::map<std::string, double> probes;
  /// Scalars of the analysis that probes can name (contact_pressure_max, contact_length, ...).
  std::map<std::string, double> globals;
  /// Extra nodal fields for the VTU (contact gap and pressure, ...): one value per node.
  std::map<std::string, VecX> point_fields;

  /// All fields zero and sized for `mesh` (a failed solve, or a mesh-only output).
  static Results zeros(int num_nodes, int num_elements, int nodes_per_element) {
    Results r;
    r.displacement = VecX::Zero(2 * num_nodes);
    r.reaction = VecX::Zero(2 * num_nodes);
    r.nodal_stress = Eigen::Matrix3Xd::Zero(3, num_nodes);
    r.element_stresses.at_points.assign(num_elements, Eigen::Matrix3Xd::Zero(3, 1));
    r.element_stresses.at_nodes.assign(num_elements, Eigen::Matrix3Xd::Zero(3, nodes_per_element));
    return r;
  }
};

}  // namespace c2d::core
