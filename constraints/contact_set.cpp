#include "constraints/contact_set.hpp"

#include <utility>

namespace c2d::constraints {

ContactSet::ContactSet(const core::Model& model, const ContactSceneSpec& spec,
                       const core::Scene& scene)
    : model_(model), spec_(spec), pairs_(model, spec, scene) {
  add_equalities();
  check_plate_rows();
}

void ContactSet::add_equalities() {
  for (size_t c = 0; c < spec_.equalities.size(); ++c) {
    const EqualitySpec& e = spec_.equalities[c];
    for (EqualityRow& row : e.constraint->rows(model_, static_cast<int>(c), e.where))
      equality_rows_.push_back(std::move(row));
  }
}

ConstrainedProblem ContactSet::problem(const SpMat& k_ff, const VecX& f_ff,
                                       const std::vector<GapRow>& rows, const VecX& u_full,
                                       bool small_strain, const VecX* u_reference) const {
  const core::DofMap& dofs = model_.dofs;
  ConstrainedProblem p;
  p.stiffness = k_ff;
  p.load = f_ff;
  p.ordering = model_.fill_order;
  pairs_.add_gap_rows(rows, u_full, p);
  if (pairs_.has_friction()) pairs_.add_friction_rows(rows, u_full, u_reference, p);
  // The equality rows: A u_f = b − (their prescribed DOFs' part).
  const std::vector<EqualityRow> equalities = equality_rows_at(u_full, small_strain);
  const int me = static_cast<int>(equalities.size());
  std::vector<Eigen::Triplet<double>> te;
  p.eq_rhs = VecX(me);
  for (int j = 0; j < me; ++j) {
    double rhs = equalities[j].rhs;
    for (const auto& [dof, a] : equalities[j].terms) {
      const int eq = dofs.equation(dof);
      if (eq >= 0)
        te.emplace_back(j, eq, a);
      else
        rhs -= a * u_full[dof];
    }
    p.eq_rhs[j] = rhs;
  }
  p.eq_jacobian = SpMat(me, dofs.num_free());
  p.eq_jacobian.setFromTriplets(te.begin(), te.end());
  p.length_scale = pairs_.length_scale();
  p.model_size = model_.model_size;
  return p;
}

}  // namespace c2d::constraints
