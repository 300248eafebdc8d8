// The equality rows of a model: the rows of its [[constraint]] tables, each made by its type's
// class in the equality registry (equality.hpp, constraints/equalities/), and the rows that
// attach its [[plate]]s (equalities/rigid_plate.hpp), at any state, with their Jacobian, values
// and curvature, and the plates' report.
#pragma once

#include <vector>

#include "constraints/constrained_problem.hpp"
#include "constraints/contact_report.hpp"
#include "constraints/contact_scene.hpp"
#include "constraints/equality.hpp"
#include "core/model.hpp"

namespace c2d::constraints {

/// Owns the [[constraint]] tables' specs and their rows (linear in u), and which of the plates'
/// rows hold a free DOF; the plates themselves are the model's.
class EqualityConstraints {
 public:
  /// Asks each [[constraint]] of `specs` for its rows on the model and checks the plates' rows
  /// against the supports (throws InputError when a selection does not fit or they disagree).
  EqualityConstraints(const core::Model& model, std::vector<EqualitySpec> specs);

  /// Neither [[constraint]] rows nor plates.
  bool empty() const { return constraint_rows_.empty() && model_.plates.empty(); }
  /// The [[constraint]] tables, in the scene's order.
  const std::vector<EqualitySpec>& specs() const { return specs_; }
  /// The rows of the scene's [[constraint]] tables (linear in u).
  const std::vector<EqualityRow>& constraint_rows() const { return constraint_rows_; }
  /// Every equality row at the full displacement u: the [[constraint]] rows, then the rows of
  /// the [[plate]]s, linearised at u unless `small_strain`.
  std::vector<EqualityRow> rows_at(const VecX& u_full, bool small_strain) const;
  /// Whether some equality row is nonlinear in u in a load-stepped run (a plate turns).
  bool has_nonlinear_rows() const { return !model_.plates.empty(); }
  /// The rows' gradients on the free DOFs (m_eq × n_free).
  SpMat jacobian(const std::vector<EqualityRow>& rows) const;
  /// Each row's value c(u) = Σ a u − rhs at the full displacement the rows were taken at.
  VecX values(const std::vector<EqualityRow>& rows, const VecX& u_full) const;
  /// −Σ μ_j ∂²c_j/∂u² on the free DOFs (zero for rows linear in u).
  SpMat geometric_stiffness(const std::vector<EqualityRow>& rows, const VecX& mu) const;
  /// The rows at u_full into `p` (see ConstrainedProblem): A u_f = b − (their prescribed DOFs'
  /// part).
  void add_rows(const VecX& u_full, bool small_strain, ConstrainedProblem& p) const;
  /// The plates' motion and transmitted force at u_full with the equality multipliers μ.
  void report_plates(const VecX& u_full, const VecX& mu, bool small_strain, ContactReport& r) const;

 private:
  /// The rows of the scene's [[constraint]] tables.
  void add_constraint_rows();
  /// Marks the plates' rows that hold a free DOF; a row on prescribed DOFs only must agree with
  /// them (else InputError) and is left out.
  void check_plate_rows();

  const core::Model& model_;
  std::vector<EqualitySpec> specs_;
  std::vector<EqualityRow> constraint_rows_;
  std::vector<char> plate_row_kept_;  ///< per row rigid_plate_rows makes, in order
};

}  // namespace c2d::constraints
