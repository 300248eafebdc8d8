// The contact and equality constraints of a model as the analysis engine uses them: the contact
// pairs (contact_pairs.hpp), the equality rows (equality_constraints.hpp) and the report on both
// (contact_reporter.hpp), and the constrained problem the strategies solve, assembled from them.
#pragma once

#include <vector>

#include "constraints/constrained_problem.hpp"
#include "constraints/constraint_strategy.hpp"
#include "constraints/contact_detection.hpp"
#include "constraints/contact_pairs.hpp"
#include "constraints/contact_report.hpp"
#include "constraints/contact_reporter.hpp"
#include "constraints/contact_scene.hpp"
#include "constraints/equality_constraints.hpp"
#include "core/model.hpp"
#include "core/tail_cholesky.hpp"

namespace c2d::constraints {

/// Owns the model's contact pairs, its equality rows and the reporter over them (which refers
/// to the other two, so a ContactSet stays where it was built); its methods hand each question
/// to the part that answers it.
class ContactSet {
 public:
  /// Resolves the selections of `spec` on the model (throws InputError when one matches nothing)
  /// and adds the seed's gap elements of a legacy scene.
  ContactSet(const core::Model& model, const ContactSceneSpec& spec, const core::Scene& scene);
  ContactSet(const ContactSet&) = delete;
  ContactSet& operator=(const ContactSet&) = delete;

  const ContactPairs& pairs() const { return pairs_; }
  const EqualityConstraints& equalities() const { return equalities_; }
  const ContactReporter& reporter() const { return reporter_; }

  bool empty() const { return pairs_.empty() && equalities_.empty(); }
  const StrategyOptions& options() const { return options_; }
  double model_size() const { return model_.model_size; }

  /// The problem on the free DOFs: K, f, and the rows linearised about u_full (the detection
  /// configuration), with prescribed DOFs moved into g0 (ContactPairs::add_gap_rows).
  /// With friction, the tangential rows too: the slip from `u_reference` (the last converged
  /// full displacement; null: the undeformed state) to u (ContactPairs::add_friction_rows).
  /// Then the equality rows at u_full (EqualityConstraints::add_rows).
  ConstrainedProblem problem(const SpMat& k_ff, const VecX& f_ff, const std::vector<GapRow>& rows,
                             const VecX& u_full, bool small_strain = true,
                             const VecX* u_reference = nullptr) const;

  // The contact pairs' questions (ContactPairs documents each).
  std::vector<GapRow> detect(const VecX& u_full, bool small_strain = false,
                             bool curvature = true) const {
    return pairs_.detect(u_full, small_strain, curvature);
  }
  double nodal_penetration(const VecX& u_full) const { return pairs_.nodal_penetration(u_full); }
  SpMat gap_jacobian(const std::vector<GapRow>& rows) const { return pairs_.gap_jacobian(rows); }
  SpMat geometric_stiffness(const std::vector<GapRow>& rows, const VecX& force) const {
    return pairs_.geometric_stiffness(rows, force);
  }
  int num_slots() const { return pairs_.num_slots(); }
  double length_scale() const { return pairs_.length_scale(); }
  double penetration_limit() const { return reporter_.penetration_limit(); }

  // The equality rows' questions (EqualityConstraints documents each).
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

  /// Fills the report of a solved state (ContactReporter::report).
  void report(const std::vector<GapRow>& rows, const ConstraintSolution& s,
              ContactReport& r) const {
    reporter_.report(rows, s, r);
  }

 private:
  const core::Model& model_;
  StrategyOptions options_;
  ContactPairs pairs_;
  EqualityConstraints equalities_;
  ContactReporter reporter_;
  /// The surface-last factor's symbolic analyses, shared by the run's solves (problem()).
  std::shared_ptr<core::TailAnalyses> analyses_ = std::make_shared<core::TailAnalyses>();
};

}  // namespace c2d::constraints
