#include "nonlinear/finite_strain_system.hpp"

#include <algorithm>
#include <cmath>

#include "core/finite_strain_kernels.hpp"
#include "core/springs.hpp"
#include "core/stopwatch.hpp"

namespace c2d::nonlinear {

using namespace c2d::core;

FiniteStrainSystem::FiniteStrainSystem(const Model& model)
    : model_(model), assembler_(model.mesh, model.dofs), f_dead_(model.external_force) {
  if (model.fill_order) solver_.set_ordering(model.fill_order, "corner_amd");
  load_scale_ = largest_external_load(model);
  extra_ = !model.springs.empty() || model.follower_matrix.nonZeros() > 0;
  // The follower pressures act at the current positions: only the dead loads stay in f_ext.
  if (model.follower_matrix.nonZeros() > 0) f_dead_ -= model.follower_reference;
  f_ext_free_ = model.dofs.restrict(f_dead_);
  if (model.follower_matrix.nonZeros() == 0) return;
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k < model.follower_matrix.outerSize(); ++k)
    for (SpMat::InnerIterator it(model.follower_matrix, k); it; ++it) {
      const int i = model.dofs.equation(static_cast<int>(it.row()));
      const int j = model.dofs.equation(static_cast<int>(it.col()));
      if (i >= 0 && j >= 0) t.emplace_back(i, j, it.value());
    }
  follower_ff_ = SpMat(model.dofs.num_free(), model.dofs.num_free());
  follower_ff_.setFromTriplets(t.begin(), t.end());
}

VecX FiniteStrainSystem::prescribed(double lambda) const {
  return prescribed_displacement(model_, lambda);
}

bool FiniteStrainSystem::admissible(const VecX& u_full) const {
  VecX f;
  return internal_force(u_full, f);
}

VecX FiniteStrainSystem::reactions(const VecX& u_full) const {
  VecX f;
  internal_force(u_full, f);
  // f_int holds the follower pressures at the current positions: only the dead loads remain.
  const VecX dead = dead_load_at(lambda_);
  for (int dof = 0; dof < model_.dofs.num_dofs(); ++dof)
    f[dof] = model_.dofs.is_constrained(dof) ? f[dof] - dead[dof] : 0.0;
  return f;
}

void FiniteStrainSystem::set_state(double lambda, const VecX& u_prescribed) {
  lambda_ = lambda;
  u_prescribed_ = u_prescribed;
  f_now_free_ = lambda * f_ext_free_;
  for (const auto& a : model_.amplitude_loads) f_now_free_ += a.at(lambda) * model_.dofs.restrict(a.force);
}

VecX FiniteStrainSystem::dead_load_at(double lambda) const {
  VecX f = lambda * f_dead_;
  for (const auto& a : model_.amplitude_loads) f += a.at(lambda) * a.force;
  return f;
}

std::string FiniteStrainSystem::evaluation_failure() const {
  return inverted_ >= 0 ? "element " + std::to_string(inverted_ + 1) + " is inverted (J <= 0)" : "";
}

VecX FiniteStrainSystem::full(const VecX& u_free) const {
  return model_.dofs.with_free(u_prescribed_, u_free);
}

bool FiniteStrainSystem::internal_force(const VecX& u, VecX& f) const {
  if (last_.u.size() == u.size() && last_.lambda == lambda_ && last_.u == u) {
    f = last_.f;
    inverted_ = last_.inverted;
    return last_.ok;
  }
  last_.u = u;
  last_.lambda = lambda_;
  last_.ok = evaluate_internal_force(u, last_.f);
  last_.inverted = inverted_;
  f = last_.f;
  return last_.ok;
}

bool FiniteStrainSystem::evaluate_internal_force(const VecX& u, VecX& f) const {
  const Mesh& mesh = model_.mesh;
  const int nn = mesh.nodes_per_element();
  f = VecX::Zero(model_.dofs.num_dofs());
  LocalVector ue(2 * nn), fe;
  inverted_ = -1;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    for (int i = 0; i < nn; ++i) ue.segment<2>(2 * i) = u.segment<2>(2 * mesh.elements[e][i]);
    if (!finite_strain_element(mesh.element_coords(e), ue,
                               model_.materials[mesh.element_material[e]], &fe, nullptr)) {
      inverted_ = e;
      return false;
    }
    for (int i = 0; i < nn; ++i) f.segment<2>(2 * mesh.elements[e][i]) += fe.segment<2>(2 * i);
  }
  add_spring_forces(model_, u, true, f);
  if (model_.follower_matrix.nonZeros() > 0) {
    VecX x = u;
    for (int v = 0; v < mesh.num_nodes(); ++v) x.segment<2>(2 * v) += mesh.nodes[v];
    f -= lambda_ * (model_.follower_matrix * x);
  }
  return true;
}

bool FiniteStrainSystem::assemble(const VecX& u, const VecX* du_constrained, VecX* lift) {
  const Stopwatch clock;
  const Mesh& mesh = model_.mesh;
  const int nn = mesh.nodes_per_element();
  bool ok = true;
  LocalVector ue(2 * nn);
  assembler_.assemble(
      [&](int e, LocalMatrix& ke) {
        for (int i = 0; i < nn; ++i) ue.segment<2>(2 * i) = u.segment<2>(2 * mesh.elements[e][i]);
        if (!finite_strain_element(mesh.element_coords(e), ue,
                                   model_.materials[mesh.element_material[e]], nullptr, &ke)) {
          ok = false;
          ke = LocalMatrix::Zero(2 * nn, 2 * nn);
        }
      },
      du_constrained, lift);
  if (extra_) tangent_ = assembler_.matrix();
  if (!model_.springs.empty()) tangent_ += spring_stiffness(model_, u, true, du_constrained, lift);
  if (model_.follower_matrix.nonZeros() > 0) {
    tangent_ -= lambda_ * follower_ff_;
    if (du_constrained && lift)
      *lift -= lambda_ * model_.dofs.restrict(model_.follower_matrix * *du_constrained);
  }
  if (!ok) {  // name the first inverted element (the parallel assembly does not say which)
    VecX f;
    internal_force(u, f);
  }
  assemble_seconds_ += clock.elapsed();
  return ok;
}

bool FiniteStrainSystem::step_predictor(const VecX& u0, VecX& load) {
  VecX du_c = VecX::Zero(u0.size()), f_int, lift;
  for (int dof = 0; dof < model_.dofs.num_dofs(); ++dof)
    if (model_.dofs.is_constrained(dof)) du_c[dof] = u_prescribed_[dof] - u0[dof];
  if (!internal_force(u0, f_int) || !assemble(u0, &du_c, &lift)) return false;
  load = f_now_free_ - model_.dofs.restrict(f_int) - lift;
  return true;
}

double FiniteStrainSystem::reaction_scale(const VecX& u_free) const {
  VecX f;
  double scale = 0.0;
  if (!internal_force(full(u_free), f)) return scale;
  for (int dof = 0; dof < model_.dofs.num_dofs(); ++dof)
    if (model_.dofs.is_constrained(dof)) scale = std::max(scale, std::abs(f[dof]));
  return scale;
}

bool FiniteStrainSystem::residual(const VecX& u_free, VecX& r) {
  VecX f;
  if (!internal_force(full(u_free), f)) return false;
  r = model_.dofs.restrict(f) - f_now_free_;
  return true;
}

bool FiniteStrainSystem::factorize_jacobian(const VecX& u_free) {
  return assemble(full(u_free)) && factorize_jacobian_assembled();
}

bool FiniteStrainSystem::factorize_jacobian_assembled() {
  if (follower_ff_.nonZeros() > 0) return lu_.factorize(matrix(), false) == SolveStatus::kConverged;
  return solver_.factorize(matrix()) == SolveStatus::kConverged;
}

bool FiniteStrainSystem::solve(const VecX& b, VecX& x) {
  if (follower_ff_.nonZeros() > 0) return lu_.solve(b, x) == SolveStatus::kConverged;
  return solver_.solve(b, x) == SolveStatus::kConverged;
}

}  // namespace c2d::nonlinear
