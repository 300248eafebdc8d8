#include "nonlinear/linear_static.hpp"

#include <cmath>

#include "core/assembler.hpp"
#include "core/elasticity_kernels.hpp"
#include "core/error_estimator.hpp"
#include "core/spd_solver.hpp"
#include "core/stopwatch.hpp"
#include "core/stress_recovery.hpp"
#include "nonlinear/contact_newton.hpp"

namespace c2d::nonlinear {

using namespace c2d::core;

namespace {

/// The contact solve: detect, solve with the scene's strategy, re-detect at the deformed
/// configuration, repeat while slave nodes change master. Fills the report and the VTU fields.
void solve_with_contact(const constraints::ContactSet& contact, const DofMap& dofs,
                        const SpMat& k_ff, const VecX& f_ff, const VecX& u_prescribed, Results& r,
                        VecX& u_free,
                        constraints::ContactReport* report_out) {
  using namespace c2d::constraints;
  const auto strategy = ConstraintStrategy::create(contact.options());
  ContactReport report;
  report.method = strategy->name();
  VecX u_full = u_prescribed;
  core::Stopwatch detection;
  std::vector<GapRow> rows = contact.detect(u_full);
  report.detection_seconds += detection.lap();
  ConstraintSolution s;
  constexpr int kMaxPasses = 5;
  std::vector<char> warm;
  for (int pass = 1; pass <= kMaxPasses; ++pass) {
    ConstrainedProblem problem = contact.problem(k_ff, f_ff, rows, u_full);
    problem.initial_active = warm;
    s = strategy->solve(problem);
    report.detection_passes = pass;
    report.iterations += s.iterations;
    report.seconds += s.seconds;
    const int offset = report.history.empty() ? 0 : report.history.back().iteration;
    for (IterationRecord rec : s.history) {
      rec.iteration += offset;
      report.history.push_back(rec);
    }
    report.penalty_history.insert(report.penalty_history.end(), s.penalty_history.begin(),
                                  s.penalty_history.end());
    if (s.status != SolveStatus::kConverged) break;
    u_full = dofs.expand(s.u);
    // The linearisation holds if detection at the deformed configuration finds the same rows
    // with the gaps the linearised rows predicted (a node sliding along a flat master changes
    // edge without changing its gap); otherwise linearise again about u, warm-started.
    detection.lap();
    std::vector<GapRow> next = contact.detect(u_full);
    report.detection_seconds += detection.lap();
    bool same = next.size() == rows.size();
    const double tol = 1e-9 * contact.model_size();
    for (size_t i = 0; same && i < rows.size(); ++i)
      same = rows[i].slave == next[i].slave &&
             std::abs(next[i].gap - s.gap[static_cast<int>(i)]) <= tol;
    if (same) break;
    std::vector<char> by_slot(contact.num_slots(), 0);
    for (size_t k = 0; k < rows.size(); ++k) by_slot[rows[k].slot] = s.active[k];
    warm.assign(next.size(), 0);
    for (size_t i = 0; i < next.size(); ++i) warm[i] = by_slot[next[i].slot];
    rows = std::move(next);
  }
  report.status = s.status;
  report.message = s.message;
  report.pivot_ratio = s.pivot_ratio;
  report.stiffness_max = k_ff.nonZeros() ? k_ff.coeffs().cwiseAbs().maxCoeff() : 0.0;
  contact.report(rows, s, report);
  r.status = s.status;
  r.message = s.message;
  r.solver.backend = report.method;
  r.solver.status = s.status;
  r.solver.message = s.message;
  r.solver.numeric_factorizations = s.factorizations;
  r.solver.symbolic_seconds = s.symbolic_seconds;
  r.solver.symbolic_analyses = s.symbolic_analyses;
  r.solver.numeric_seconds = s.numeric_seconds;
  r.solver.solve_seconds = s.solve_seconds;
  u_free = s.u;
  store_contact_results(report, static_cast<int>(u_prescribed.size() / 2), r);
  if (report_out) *report_out = std::move(report);
}
}  // namespace

Results solve_linear_static(const Model& model, const AnalysisSpec& analysis,
                            const constraints::ContactSet* contact,
                            constraints::ContactReport* contact_report) {
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
  const VecX rhs = dofs.restrict(model.external_force) - lift;
  r.time.assemble = clock.lap();

  VecX u_free;
  if (contact && !contact->empty()) {
    solve_with_contact(*contact, dofs, assembler.matrix(), rhs, u_prescribed, r, u_free, contact_report);
  } else {
    SpdSolver solver(analysis.solver == "ldlt" ? SpdSolver::Backend::kEigenLdlt
                                               : SpdSolver::Backend::kCholmod);
    r.status = solver.factorize(assembler.matrix());
    if (r.status == SolveStatus::kConverged) r.status = solver.solve(rhs, u_free);
    r.solver = solver.report();
    if (r.status != SolveStatus::kConverged) r.message = r.solver.message;
  }
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
  r.time.recovery = clock.lap();
  return r;
}

}  // namespace c2d::nonlinear
