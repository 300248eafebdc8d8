#include "nonlinear/linear_static.hpp"

#include <cmath>

#include "core/linear_solve.hpp"
#include "core/stopwatch.hpp"
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
  if (!contact || contact->empty()) return solve_linear(model, analysis);
  return solve_linear(model, analysis,
                      [&](const SpMat& k_ff, const VecX& rhs, const VecX& u_prescribed,
                          VecX& u_free, Results& r) {
                        solve_with_contact(*contact, model.dofs, k_ff, rhs, u_prescribed, r,
                                           u_free, contact_report);
                      });
}

}  // namespace c2d::nonlinear
