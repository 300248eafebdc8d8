#include "core/linear_solve.hpp"

#include "core/assembler.hpp"
#include "core/elasticity_kernels.hpp"
#include "core/error_estimator.hpp"
#include "core/spd_solver.hpp"
#include "core/springs.hpp"
#include "core/stopwatch.hpp"
#include "core/stress_recovery.hpp"

namespace c2d::core {

namespace {

void solve_plain(const Model& model, const AnalysisSpec& analysis, const SpMat& k_ff,
                 const VecX& rhs, VecX& u_free, Results& r) {
  SpdSolver solver(analysis.solver == "ldlt" ? SpdSolver::Backend::kEigenLdlt
                                             : SpdSolver::Backend::kCholmod);
  if (model.fill_order) solver.set_ordering(model.fill_order, "corner_amd");
  r.status = solver.factorize(k_ff);
  if (r.status == SolveStatus::kConverged) r.status = solver.solve(rhs, u_free);
  r.solver = solver.report();
  if (r.status != SolveStatus::kConverged) r.message = r.solver.message;
}

}  // namespace

Results solve_linear(const Model& model, const AnalysisSpec& analysis, const LinearSolve& solve) {
  Results r;
  const Mesh& mesh = model.mesh;
  const DofMap& dofs = model.dofs;
  r.time.mesh = model.mesh_seconds;

  Stopwatch clock;
  Assembler assembler(mesh, dofs);
  assembler.set_threads(0);  // element_stiffness is a pure function of the element
  const VecX u_prescribed = dofs.expand(VecX::Zero(dofs.num_free()));
  VecX lift;
  assembler.assemble(
      [&](int e, LocalMatrix& ke) {
        ke = element_stiffness(mesh.element_coords(e), model.materials[mesh.element_material[e]]);
      },
      &u_prescribed, &lift);
  // Springs: their stiffness joins K (and their coupling to prescribed DOFs the lift).
  SpMat with_springs;
  if (!model.springs.empty())
    with_springs = assembler.matrix() + spring_stiffness(model, VecX::Zero(dofs.num_dofs()), false,
                                                         &u_prescribed, &lift);
  const SpMat& k_ff = model.springs.empty() ? assembler.matrix() : with_springs;
  const VecX f_ext = model.external_force_at(1.0);
  const VecX rhs = dofs.restrict(f_ext) - lift;
  r.time.assemble = clock.lap();

  VecX u_free;
  if (solve) solve(k_ff, rhs, u_prescribed, u_free, r);
  else solve_plain(model, analysis, k_ff, rhs, u_free, r);
  r.time.solve = clock.lap();
  // A contact method that stopped at its iteration limit or on a cycle still has a displacement
  // worth reporting; any other failure has none.
  const bool usable = (r.status == SolveStatus::kConverged || r.status == SolveStatus::kCycling ||
                       r.status == SolveStatus::kMaxIterations) &&
                      u_free.size() == dofs.num_free() && u_free.allFinite();
  if (!usable) {
    const Results zeros =
        Results::zeros(mesh.num_nodes(), mesh.num_elements(), mesh.nodes_per_element());
    r.displacement = zeros.displacement;
    r.reaction = zeros.reaction;
    r.element_stresses = zeros.element_stresses;
    r.nodal_stress = zeros.nodal_stress;
    return r;
  }
  r.displacement = dofs.expand(u_free);

  clock.lap();
  // Reactions: internal force minus external load on the constrained DOFs.
  r.reaction = VecX::Zero(dofs.num_dofs());
  const int nn = mesh.nodes_per_element();
  LocalVector ue(2 * nn);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    bool touches = false;
    for (int i = 0; i < nn; ++i) {
      const int n = mesh.elements[e][i];
      touches = touches || dofs.is_constrained(2 * n) || dofs.is_constrained(2 * n + 1);
      ue.segment<2>(2 * i) = r.displacement.segment<2>(2 * n);
    }
    if (!touches) continue;
    const LocalVector fe =
        element_stiffness(mesh.element_coords(e), model.materials[mesh.element_material[e]]) * ue;
    for (int i = 0; i < nn; ++i)
      for (int c = 0; c < 2; ++c) {
        const int dof = 2 * mesh.elements[e][i] + c;
        if (dofs.is_constrained(dof)) r.reaction[dof] += fe[2 * i + c];
      }
  }
  VecX spring_force = VecX::Zero(dofs.num_dofs());
  add_spring_forces(model, r.displacement, false, spring_force);
  for (int dof = 0; dof < dofs.num_dofs(); ++dof)
    if (dofs.is_constrained(dof)) r.reaction[dof] += spring_force[dof] - f_ext[dof];

  r.element_stresses = compute_element_stresses(mesh, model.materials, r.displacement);
  r.nodal_stress = smooth_stresses(mesh, model.materials, r.element_stresses, analysis.smoothing);
  r.error = estimate_error(mesh, model.materials, r.element_stresses, r.nodal_stress,
                           analysis.target_error);
  r.time.recovery = clock.lap();
  return r;
}

}  // namespace c2d::core
