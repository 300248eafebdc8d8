#include "constraints/equality_constraints.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "constraints/equalities/rigid_plate.hpp"
#include "core/errors.hpp"

namespace c2d::constraints {

EqualityConstraints::EqualityConstraints(const core::Model& model, std::vector<EqualitySpec> specs)
    : model_(model), specs_(std::move(specs)) {
  add_constraint_rows();
  check_plate_rows();
}

void EqualityConstraints::add_constraint_rows() {
  for (size_t c = 0; c < specs_.size(); ++c) {
    const EqualitySpec& e = specs_[c];
    for (EqualityRow& row : e.constraint->rows(model_, static_cast<int>(c), e.where))
      constraint_rows_.push_back(std::move(row));
  }
}

void EqualityConstraints::check_plate_rows() {
  const core::DofMap& dofs = model_.dofs;
  // At λ = 1, where the motions' amplitudes turn, and halfway between: translations are
  // piecewise linear between the turns, so two that agree there agree everywhere; a rotation's
  // arc is not, and the halfway points catch one that leaves the other between turns.
  std::vector<double> turns = {0.0, 1.0};
  for (const core::Amplitude& a : model_.motion_amplitudes)
    for (const auto& [lambda, value] : a.table) turns.push_back(lambda);
  std::sort(turns.begin(), turns.end());
  turns.erase(std::unique(turns.begin(), turns.end()), turns.end());
  std::vector<double> at = {1.0};
  if (!model_.motion_amplitudes.empty())
    for (size_t k = 0; k < turns.size(); ++k) {
      at.push_back(turns[k]);
      if (k + 1 < turns.size()) at.push_back(0.5 * (turns[k] + turns[k + 1]));
    }
  std::vector<VecX> motion;  // the prescribed displacements there, once for every plate
  for (double lambda : at) motion.push_back(core::prescribed_displacement(model_, lambda));
  std::vector<EqualityRow> rows;
  for (size_t p = 0; p < model_.plates.size(); ++p) {
    for (size_t j = 0; j < at.size(); ++j) {
      const VecX& u = motion[j];
      rows.clear();
      rigid_plate_rows(model_, static_cast<int>(p), u, true, rows);
      const VecX residual = values(rows, u);
      for (size_t k = 0; k < rows.size(); ++k) {
        bool free = false;
        for (const auto& [dof, a] : rows[k].terms)
          free = free || (a != 0.0 && !dofs.is_constrained(dof));
        if (j == 0) plate_row_kept_.push_back(free);
        const double value = residual[static_cast<int>(k)];
        if (!free && std::abs(value) > 1e-9 * model_.model_size)
          throw InputError(model_.plates[p].where + ": the plate's prescribed motion moves node " +
                           std::to_string(model_.plates[p].nodes[0] + 1) +
                           "'s support away from what the support prescribes (the two disagree " +
                           "by " + number_text(value) + " at load factor " + number_text(at[j]) +
                           ")");
      }
    }
  }
}

std::vector<EqualityRow> EqualityConstraints::rows_at(const VecX& u_full, bool small_strain) const {
  std::vector<EqualityRow> rows = constraint_rows_;
  if (model_.plates.empty()) return rows;
  std::vector<EqualityRow> plate;
  for (size_t p = 0; p < model_.plates.size(); ++p)
    rigid_plate_rows(model_, static_cast<int>(p), u_full, small_strain, plate);
  for (size_t k = 0; k < plate.size(); ++k)
    if (plate_row_kept_[k]) rows.push_back(std::move(plate[k]));
  return rows;
}

SpMat EqualityConstraints::jacobian(const std::vector<EqualityRow>& rows) const {
  const core::DofMap& dofs = model_.dofs;
  std::vector<Eigen::Triplet<double>> t;
  for (size_t j = 0; j < rows.size(); ++j)
    for (const auto& [dof, a] : rows[j].terms) {
      const int eq = dofs.equation(dof);
      if (eq >= 0 && a != 0.0) t.emplace_back(static_cast<int>(j), eq, a);
    }
  SpMat a(static_cast<int>(rows.size()), dofs.num_free());
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

VecX EqualityConstraints::values(const std::vector<EqualityRow>& rows, const VecX& u_full) const {
  VecX c(static_cast<int>(rows.size()));
  for (size_t j = 0; j < rows.size(); ++j) {
    double v = -rows[j].rhs;
    for (const auto& [dof, a] : rows[j].terms) v += a * u_full[dof];
    c[static_cast<int>(j)] = v;
  }
  return c;
}

SpMat EqualityConstraints::geometric_stiffness(const std::vector<EqualityRow>& rows,
                                               const VecX& mu) const {
  const core::DofMap& dofs = model_.dofs;
  std::vector<Eigen::Triplet<double>> t;
  for (size_t j = 0; j < rows.size(); ++j) {
    const double m = mu[static_cast<int>(j)];
    if (m == 0.0) continue;
    for (const auto& [a, b, value] : rows[j].curvature) {
      const int ea = dofs.equation(a), eb = dofs.equation(b);
      if (ea >= 0 && eb >= 0) t.emplace_back(ea, eb, -m * value);
    }
  }
  SpMat k(dofs.num_free(), dofs.num_free());
  k.setFromTriplets(t.begin(), t.end());
  return k;
}

void EqualityConstraints::add_rows(const VecX& u_full, bool small_strain,
                                   ConstrainedProblem& p) const {
  const core::DofMap& dofs = model_.dofs;
  const std::vector<EqualityRow> rows = rows_at(u_full, small_strain);
  const int me = static_cast<int>(rows.size());
  std::vector<Eigen::Triplet<double>> te;
  p.eq_rhs = VecX(me);
  for (int j = 0; j < me; ++j) {
    double rhs = rows[j].rhs;
    for (const auto& [dof, a] : rows[j].terms) {
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
}

void EqualityConstraints::report_plates(const VecX& u_full, const VecX& mu, bool small_strain,
                                        ContactReport& r) const {
  r.plates.clear();
  if (model_.plates.empty()) return;
  const std::vector<EqualityRow> rows = rows_at(u_full, small_strain);
  for (const core::RigidPlate& plate : model_.plates) {
    PlateResult out;
    out.name = plate.name;
    out.u = u_full.segment<2>(plate.dof);
    out.rotation = u_full[plate.dof + 2];
    // The attachment's force on the plate is Σ μ ∂c/∂q; the plate's on the structure its opposite.
    Eigen::Vector3d on_plate = Eigen::Vector3d::Zero();
    for (size_t j = 0; j < rows.size() && static_cast<int>(j) < mu.size(); ++j)
      for (const auto& [dof, a] : rows[j].terms)
        if (dof >= plate.dof && dof < plate.dof + 3)
          on_plate[dof - plate.dof] += mu[static_cast<int>(j)] * a;
    out.force = -on_plate.head<2>();
    out.moment = -on_plate[2];
    r.plates.push_back(out);
  }
}

}  // namespace c2d::constraints
