#include "nonlinear/linear_static.hpp"

#include <chrono>

#include "core/assembler.hpp"
#include "core/elasticity_kernels.hpp"
#include "core/error_estimator.hpp"
#include "core/spd_solver.hpp"
#include "core/stress_recovery.hpp"

namespace c2d::nonlinear {

using namespace c2d::core;

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

Results solve_linear_static(const Model& model, const AnalysisSpec& analysis) {
  Results r;
  const Mesh& mesh = model.mesh;
  const DofMap& dofs = model.dofs;
  r.time.mesh = model.mesh_seconds;

  auto t = std::chrono::steady_clock::now();
  Assembler assembler(mesh, dofs);
  const VecX u_prescribed = dofs.expand(VecX::Zero(dofs.num_free()));
  VecX lift;
  assembler.assemble(
      [&](int e, LocalMatrix& ke) {
        ke = element_stiffness(mesh.element_coords(e), model.materials[mesh.element_material[e]]);
      },
      &u_prescribed, &lift);
  const VecX rhs = dofs.restrict(model.external_force) - lift;
  r.time.assemble = seconds_since(t);

  t = std::chrono::steady_clock::now();
  SpdSolver solver(analysis.solver == "ldlt" ? SpdSolver::Backend::kEigenLdlt
                                             : SpdSolver::Backend::kCholmod);
  VecX u_free;
  r.status = solver.factorize(assembler.matrix());
  if (r.status == SolveStatus::kConverged) r.status = solver.solve(rhs, u_free);
  r.solver = solver.report();
  r.time.solve = seconds_since(t);
  if (r.status != SolveStatus::kConverged) {
    Results failed = Results::zeros(mesh.num_nodes(), mesh.num_elements(), mesh.nodes_per_element());
    failed.status = r.status;
    failed.message = r.solver.message;
    failed.solver = r.solver;
    failed.time = r.time;
    return failed;
  }
  r.displacement = dofs.expand(u_free);

  t = std::chrono::steady_clock::now();
  // Reactions: internal force minus external load on the constrained DOFs.
  r.reaction = VecX::Zero(mesh.num_dofs());
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
  for (int dof = 0; dof < mesh.num_dofs(); ++dof)
    if (dofs.is_constrained(dof)) r.reaction[dof] -= model.external_force[dof];

  r.element_stresses = compute_element_stresses(mesh, model.materials, r.displacement);
  r.nodal_stress = smooth_stresses(mesh, model.materials, r.element_stresses, analysis.smoothing);
  r.error = estimate_error(mesh, model.materials, r.element_stresses, r.nodal_stress,
                           analysis.target_error);
  r.time.recovery = seconds_since(t);
  return r;
}

}  // namespace c2d::nonlinear
