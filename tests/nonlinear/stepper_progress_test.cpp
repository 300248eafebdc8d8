// The load stepper and Newton must make progress or say they cannot (issue 33, item 5):
// Newton stops an attempt that makes no progress instead of running to its iteration limit, and
// a run that was cut back grows its increment back to the nominal one.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "constraints/contact_scene.hpp"
#include "constraints/contact_set.hpp"
#include "core/model.hpp"
#include "core/scene.hpp"
#include "nonlinear/load_stepper.hpp"
#include "nonlinear/newton_solver.hpp"

namespace c2d {
namespace {

/// One scalar equation f(x) = 0 with its exact derivative.
class Scalar : public nonlinear::NewtonSystem {
 public:
  Scalar(double (*f)(double), double (*df)(double)) : f_(f), df_(df) {}
  bool residual(const VecX& u, VecX& r) override {
    r = VecX::Constant(1, f_(u[0]));
    return true;
  }
  bool factorize_jacobian(const VecX& u) override {
    slope_ = df_(u[0]);
    return slope_ != 0.0;
  }
  bool solve(const VecX& b, VecX& x) override {
    x = VecX::Constant(1, b[0] / slope_);
    return true;
  }

 private:
  double (*f_)(double);
  double (*df_)(double);
  double slope_ = 1.0;
};

// Newton on x³ − 2x + 2 from 0 cycles exactly between 0 and 1 (residuals 2, 1, 2, 1, ...): no
// iterate ever goes below 0.9 of the least residual after the second, so the attempt stops
// `stalled` after 2 + 5 Jacobians, not at the limit of 25. A convergent equation is untouched:
// x³ − 2 from 1 reaches 2^(1/3) to 1e-12.
TEST(NewtonProgress, StopsATwoCycleAndLeavesConvergenceAlone) {
  nonlinear::NewtonOptions o;
  o.line_search = false;
  o.max_iterations = 25;
  o.residual_tolerance = 1e-14;
  Scalar cycle([](double x) { return x * x * x - 2 * x + 2; },
               [](double x) { return 3 * x * x - 2; });
  VecX x = VecX::Zero(1);
  const nonlinear::NewtonReport r = nonlinear::solve_newton(cycle, x, o);
  EXPECT_EQ(r.status, SolveStatus::kStalled);
  EXPECT_NE(r.message.find("no progress"), std::string::npos) << r.message;
  EXPECT_EQ(r.factorizations, 6);  // Jacobians at 0, 1, 0, 1, 0, 1; the 7th call stops it
  EXPECT_LE(r.iterations, 7);

  Scalar root([](double x) { return x * x * x - 2; }, [](double x) { return 3 * x * x; });
  x = VecX::Ones(1);
  const nonlinear::NewtonReport ok = nonlinear::solve_newton(root, x, o);
  EXPECT_EQ(ok.status, SolveStatus::kConverged) << ok.message;
  EXPECT_NEAR(x[0], std::cbrt(2.0), 1e-12);
}

// examples/drag.toml with lagrange: a block pressed by P = 5 and dragged three of its widths
// with Coulomb friction (μ = 0.3). Its first steps are cut back; the increment must grow back
// to the nominal one (before, one growth per cutback kept the run at 1/16 of it: 1,616 steps
// for 30, 98 s), and the state is Coulomb's: normal force P and the nodes' friction forces
// (each along its own tangent) μP within 2e-4 (the base's surface tilts under the block, so
// Σλ_n differs from P by the friction's vertical share: 1.5e-4 measured). The resultant's
// component along the block's reference tangent, which the report gives as its tangential
// force, is below μP by that tilt (1.4970 measured).
TEST(StepperProgress, GrowsBackToTheNominalIncrementAfterCutbacks) {
  const core::Scene sc = core::load_scene(std::string(C2D_SOURCE_DIR) + "/examples/drag.toml");
  const core::Model model = core::build_model(sc);
  const constraints::ContactSet contact(model, constraints::parse_contact_scene(sc, "lagrange"),
                                        sc);
  nonlinear::StepperOptions o;
  o.steps = sc.analysis.steps;
  std::vector<nonlinear::StepRecord> trace;
  constraints::ContactReport report;
  const core::Results r =
      nonlinear::solve_geometric_nonlinear(model, sc.analysis, o, &trace, &contact, &report);
  ASSERT_EQ(r.status, SolveStatus::kConverged) << r.message;
  int converged = 0;
  for (const nonlinear::StepRecord& s : trace) converged += s.newton.status == SolveStatus::kConverged;
  EXPECT_LE(converged, 36);
  EXPECT_LE(trace.size(), 48u);  // attempts
  EXPECT_NEAR(report.total_force, 5.0, 2e-4 * 5.0);
  double friction = 0.0;
  for (const constraints::ContactNodeResult& n : report.nodes) friction += n.tangent_force;
  EXPECT_NEAR(std::abs(friction), 1.5, 2e-4 * 1.5);
  EXPECT_NEAR(std::abs(report.tangent_force), 1.5, 3e-3 * 1.5);
}

}  // namespace
}  // namespace c2d
