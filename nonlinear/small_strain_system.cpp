#include <algorithm>
#include <cmath>

#include "core/assembler.hpp"
#include "core/elasticity_kernels.hpp"
#include "core/springs.hpp"
#include "core/stopwatch.hpp"
#include "nonlinear/finite_strain_system.hpp"
#include "nonlinear/structural_system.hpp"

namespace c2d::nonlinear {

using namespace c2d::core;

std::unique_ptr<StructuralSystem> make_structural_system(const Model& model,
                                                         const AnalysisSpec& analysis) {
  if (analysis.geometric_nonlinearity) return std::make_unique<FiniteStrainSystem>(model);
  return std::make_unique<SmallStrainSystem>(model, analysis);
}

double largest_external_load(const Model& model) {
  VecX peak = model.dofs.restrict(model.external_force).cwiseAbs();
  for (const auto& a : model.amplitude_loads)  // the largest each load reaches
    peak += a.amplitude.peak() * model.dofs.restrict(a.force).cwiseAbs();
  return peak.size() ? peak.maxCoeff() : 0.0;
}

SmallStrainSystem::SmallStrainSystem(const Model& model, const AnalysisSpec& analysis)
    : model_(model),
      solver_(analysis.solver == "ldlt" ? SpdSolver::Backend::kEigenLdlt
                                        : SpdSolver::Backend::kCholmod) {
  if (model.fill_order) solver_.set_ordering(model.fill_order, "corner_amd");
  const Stopwatch clock;
  const DofMap& dofs = model.dofs;
  const auto kernel = [&](int e, LocalMatrix& ke) {
    ke = element_stiffness(model.mesh.element_coords(e),
                           model.materials[model.mesh.element_material[e]]);
  };
  // The lift of the prescribed values that grow as λ, and of each motion amplitude's own
  // (K_fc is linear in u_c).
  const auto assemble = [&](const VecX& u_c, VecX& lift) {
    Assembler assembler(model.mesh, dofs);
    assembler.set_threads(0);  // element_stiffness is a pure function of the element
    assembler.assemble(kernel, &u_c, &lift);
    SpMat k = std::move(assembler.matrix());
    if (!model.springs.empty())
      k += spring_stiffness(model, VecX::Zero(dofs.num_dofs()), false, &u_c, &lift);
    return k;
  };
  k_ff_ = assemble(prescribed_group(model, -1), lift_one_);
  lift_amplitude_.resize(model.motion_amplitudes.size());
  for (size_t k = 0; k < lift_amplitude_.size(); ++k)
    assemble(prescribed_group(model, static_cast<int>(k)), lift_amplitude_[k]);
  assemble_seconds_ = clock.elapsed();
  load_scale_ = largest_external_load(model);
  set_state(0.0, prescribed(0.0));
}

VecX SmallStrainSystem::prescribed(double lambda) const {
  return prescribed_values(model_, lambda);
}

void SmallStrainSystem::set_state(double lambda, const VecX& u_prescribed) {
  lambda_ = lambda;
  u_prescribed_ = u_prescribed;
  rhs_ = model_.dofs.restrict(model_.external_force_at(lambda)) - lambda * lift_one_;
  for (size_t k = 0; k < lift_amplitude_.size(); ++k)
    rhs_ -= model_.motion_amplitudes[k].at(lambda) * lift_amplitude_[k];
}

VecX SmallStrainSystem::full(const VecX& u_free) const {
  return model_.dofs.with_free(u_prescribed_, u_free);
}

bool SmallStrainSystem::factorize_jacobian_assembled() {
  // K never changes: one factorisation serves the run.
  if (!factorized_) factorized_ = solver_.factorize(k_ff_) == SolveStatus::kConverged;
  return factorized_;
}

bool SmallStrainSystem::solve(const VecX& b, VecX& x) {
  return factorized_ && solver_.solve(b, x) == SolveStatus::kConverged;
}

bool SmallStrainSystem::step_predictor(const VecX& u0, VecX& load) {
  // rhs carries the whole prescribed lift K_fc u_c, so only the free part of u0 remains.
  load = rhs_ - k_ff_ * model_.dofs.restrict(u0);
  return true;
}

bool SmallStrainSystem::residual(const VecX& u_free, VecX& r) {
  r = k_ff_ * u_free - rhs_;
  return true;
}

VecX SmallStrainSystem::reactions(const VecX& u) const {
  // K u on the constrained DOFs, from the elements that touch one, plus the springs' forces,
  // less the external load there.
  const Mesh& mesh = model_.mesh;
  const DofMap& dofs = model_.dofs;
  VecX f = VecX::Zero(dofs.num_dofs());
  const int nn = mesh.nodes_per_element();
  LocalVector ue(2 * nn);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    bool touches = false;
    for (int i = 0; i < nn; ++i) {
      const int n = mesh.elements[e][i];
      touches = touches || dofs.is_constrained(2 * n) || dofs.is_constrained(2 * n + 1);
      ue.segment<2>(2 * i) = u.segment<2>(2 * n);
    }
    if (!touches) continue;
    const LocalVector fe =
        element_stiffness(mesh.element_coords(e), model_.materials[mesh.element_material[e]]) * ue;
    for (int i = 0; i < nn; ++i)
      for (int c = 0; c < 2; ++c)
        if (const int dof = 2 * mesh.elements[e][i] + c; dofs.is_constrained(dof)) f[dof] += fe[2 * i + c];
  }
  add_spring_forces(model_, u, false, f);
  const VecX f_ext = model_.external_force_at(lambda_);
  for (int dof = 0; dof < dofs.num_dofs(); ++dof) f[dof] = dofs.is_constrained(dof) ? f[dof] - f_ext[dof] : 0.0;
  return f;
}

double SmallStrainSystem::reaction_scale(const VecX& u_free) const {
  return reactions(full(u_free)).cwiseAbs().maxCoeff();
}

}  // namespace c2d::nonlinear
