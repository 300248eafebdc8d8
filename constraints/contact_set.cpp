#include "constraints/contact_set.hpp"

namespace c2d::constraints {

ContactSet::ContactSet(const core::Model& model, const ContactSceneSpec& spec,
                       const core::Scene& scene)
    : model_(model),
      options_(spec.options),
      pairs_(model, spec, scene),
      equalities_(model, spec.equalities),
      reporter_(model, pairs_, equalities_, options_) {}

ConstrainedProblem ContactSet::problem(const SpMat& k_ff, const VecX& f_ff,
                                       const std::vector<GapRow>& rows, const VecX& u_full,
                                       bool small_strain, const VecX* u_reference) const {
  ConstrainedProblem p;
  p.stiffness = k_ff;
  p.load = f_ff;
  p.ordering = model_.fill_order;
  // Finite strain factorises K_T at every iterate, a new condensation each time; a small-strain
  // K is factorised once or twice a run, and a kept analysis would only cost its memory (a
  // 1.2M-DOF Hertz run: 120 MB).
  if (!small_strain) p.analyses = analyses_;
  pairs_.add_gap_rows(rows, u_full, p);
  if (pairs_.has_friction()) pairs_.add_friction_rows(rows, u_full, u_reference, p);
  equalities_.add_rows(u_full, small_strain, p);
  p.length_scale = pairs_.length_scale();
  p.model_size = model_.model_size;
  return p;
}

}  // namespace c2d::constraints
