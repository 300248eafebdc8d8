#include "nonlinear/linear_static.hpp"

#include <cmath>

#include "core/linear_solve.hpp"
#include "core/stopwatch.hpp"
#include "nonlinear/contact_newton.hpp"
#include "nonlinear/structural_system.hpp"

namespace c2d::nonlinear {

using namespace c2d::core;

namespace {

/// The contact solve of a linear analysis: the constrained step of the load-stepped analysis,
/// taken once on the small-strain system (K_ff constant, K_σ = 0) to the full load. Fills the
/// report and the VTU fields.
void solve_with_contact_step(const constraints::ContactSet& contact, const Model& model,
                             const SpMat& k_ff, const VecX& rhs, const VecX& u_prescribed,
                             Results& r, VecX& u_free, constraints::ContactReport* report_out) {
  using namespace c2d::constraints;
  const auto strategy = ConstraintStrategy::create(contact.options());
  SmallStrainSystem system(model, k_ff, rhs, u_prescribed);
  ContactStepInput in;
  in.u_free = VecX::Zero(model.dofs.num_free());
  in.u_prev_full = VecX::Zero(model.dofs.num_dofs());
  in.newton.residual_scale = rhs.size() ? rhs.cwiseAbs().maxCoeff() : 0.0;
  in.floor_scale = residual_floor_scale(model);
  ContactStepResult step = solve_contact_step(system, contact, *strategy, in);

  ContactReport report;
  report.method = strategy->name();
  report.status = step.status;
  report.message = step.message;
  report.iterations = step.strategy.iterations;
  report.detection_passes = static_cast<int>(step.iterations.size());
  report.seconds = step.strategy.seconds;
  report.detection_seconds = step.detection_seconds;
  report.history = step.strategy.history;
  report.penalty_history = step.strategy.penalty_history;
  report.pivot_ratio = step.strategy.pivot_ratio;
  report.stiffness_max = k_ff.nonZeros() ? k_ff.coeffs().cwiseAbs().maxCoeff() : 0.0;
  if (step.state.gap.size() == static_cast<int>(step.rows.size()))
    contact.report(step.rows, step.state, report);
  if (step.u_free.size() == model.dofs.num_free())
    contact.report_plates(model.dofs.expand(step.u_free), step.state.eq_multiplier, true, report);
  report.measured_penetration = step.measured_penetration;
  report.penetration_tolerance = step.penetration_tolerance;
  r.status = step.status;
  r.message = step.message;
  r.solver.backend = report.method;
  r.solver.status = step.status;
  r.solver.message = step.message;
  r.solver.numeric_factorizations = step.strategy.factorizations + step.newton.factorizations;
  r.solver.symbolic_seconds = step.strategy.symbolic_seconds;
  r.solver.symbolic_analyses = step.strategy.symbolic_analyses;
  r.solver.numeric_seconds = step.strategy.numeric_seconds;
  r.solver.solve_seconds = step.strategy.solve_seconds;
  if (std::isfinite(step.strategy.pivot_ratio)) r.solver.pivot_ratio = step.strategy.pivot_ratio;
  static_cast<FactorInfo&>(r.solver) = step.strategy.factor;
  u_free = step.u_free;
  store_contact_results(report, model.mesh.num_nodes(), r);
  if (report_out) *report_out = std::move(report);
}
}  // namespace

Results solve_linear_static(const Model& model, const AnalysisSpec& analysis,
                            const constraints::ContactSet* contact,
                            constraints::ContactReport* contact_report) {
  if (!contact || contact->empty()) return solve_linear(model, analysis);
  return solve_linear(model, analysis,
                      [&](const SpMat& k_ff, const VecX& rhs, const VecX& u_prescribed,
                          VecX& u_free, Results& r) {
                        solve_with_contact_step(*contact, model, k_ff, rhs, u_prescribed, r,
                                                u_free, contact_report);
                      });
}

}  // namespace c2d::nonlinear
