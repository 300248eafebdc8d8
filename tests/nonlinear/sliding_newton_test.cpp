// Consistent linearisation inside Newton (issue 15, item 8 and finding 9): a block pressed onto
// a longer block and dragged three of its own lengths along it, frictionless, 30 load steps,
// finite strain. The rows are detected again at every iterate with their exact derivatives and
// the method's linearisation carries the contact's geometric stiffness, so Newton converges
// quadratically while the slave nodes slide from one master edge to the next. Before, each step took about 8 outer passes converging linearly
// (residual 0.02, 4e-4, 9e-6, 5e-7, 1e-8 at successive passes).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "constraints/contact_scene.hpp"
#include "constraints/contact_set.hpp"
#include "core/model.hpp"
#include "core/probes.hpp"
#include "core/scene.hpp"
#include "nonlinear/load_stepper.hpp"
#include "scene_run.hpp"

using namespace c2d;
using namespace c2d::nonlinear;

namespace {

std::string sliding_scene(const std::string& element, const std::string& detection) {
  return test::block_drag_scene(element, detection, 0.5, "");
}

struct Sliding {
  core::Results results;
  std::vector<StepRecord> steps;
};

Sliding drag(const std::string& element, const std::string& detection,
             const std::string& method) {
  const core::Scene scene = core::parse_scene(sliding_scene(element, detection), "slide.toml");
  const core::Model model = core::build_model(scene);
  const constraints::ContactSet contact(
      model, constraints::parse_contact_scene(scene, method), scene);
  StepperOptions o;
  o.steps = scene.analysis.steps;
  Sliding s;
  s.results = solve_geometric_nonlinear(model, scene.analysis, o, &s.steps, &contact);
  if (s.results.status == SolveStatus::kConverged)
    s.results.probes = core::evaluate_probes(scene, model, s.results);
  return s;
}

}  // namespace

TEST(SlidingContact, NewtonConvergesQuadraticallyAndOuterIterationsOnlyConfirm) {
  for (const std::string element : {"T3", "T6"})
    for (const std::string detection : {"node_to_segment", "mortar"})
      for (const std::string method : {"lagrange", "penalty"}) {
        const std::string name = element + " " + detection + " " + method;
        const Sliding s = drag(element, detection, method);
        ASSERT_EQ(s.results.status, SolveStatus::kConverged) << name << ": " << s.results.message;
        int steps = 0, newton = 0, factorizations = 0, cutbacks = 0;
        for (const StepRecord& r : s.steps) {
          cutbacks += r.attempt > 0;
          factorizations += r.factorizations;
          if (r.newton.status != SolveStatus::kConverged) continue;
          ++steps;
          newton += r.newton.iterations;
        }
        EXPECT_EQ(steps, 30) << name;
        EXPECT_EQ(cutbacks, 0) << name;
        // Quadratic convergence: every iterate (the method's step with its set updated, or a
        // Newton step with the set held) is one Newton iteration and one factorisation. From
        // the third step on, each step starts where the last two increments extrapolate to
        // (the drag goes on in proportion), with the contact's geometric stiffness under the
        // last step's forces: 2.3 to 3.0 a step with multipliers, 3.1 to 3.7 with a penalty
        // (from the tangent predictor, 3.5 to 3.8 and 4.3 to 5.0: a penalty's first iterate
        // there carries k times the gap the linear step across the curved master missed).
        EXPECT_LE(newton, (method == "lagrange" ? 3.2 : 4.0) * 30) << name;
        EXPECT_LE(factorizations, (method == "lagrange" ? 3.2 : 4.0) * 30) << name;
        EXPECT_LE(newton, factorizations) << name;
        // Frictionless: the tangential reaction comes only from the tilt of the indented
        // surface at the slider's corners, a discretisation effect.
        const double fx = s.results.probes.at("fx"), fy = s.results.probes.at("fy");
        EXPECT_GT(std::abs(fy), 1.0) << name;
        EXPECT_LT(std::abs(fx), 1e-3 * std::abs(fy)) << name << ": fx " << fx << " fy " << fy;
        RecordProperty(name + " newton", newton);
      }
}
