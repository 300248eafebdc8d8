// A scene solved as `contact2d run` solves it, for the nonlinear module's tests: the model, its
// constraint set (contacts, [[constraint]]s, [[plate]]s) enforced by `method`, a linear solve
// or load steps as the scene's analysis says, and the probes when it converged.
#pragma once

#include <string>
#include <vector>

#include "constraints/contact_scene.hpp"
#include "constraints/contact_set.hpp"
#include "core/model.hpp"
#include "core/probes.hpp"
#include "core/scene.hpp"
#include "nonlinear/load_stepper.hpp"

namespace c2d::test {

struct SceneRun {
  core::Results results;
  constraints::ContactReport report;
  std::vector<nonlinear::StepRecord> trace;  ///< load-stepped runs
};

/// A 1 × 0.5 slider (its left end at x0) pressed 0.01 into a 6 × 1 base and dragged 3 to the
/// right by its top edge, 30 load steps, finite strain, E = 1000, ν = 0.3; `extra` goes into
/// its [[contact]] table (a friction law). Probes fx, fy: the top edge's reactions.
inline std::string block_drag_scene(const std::string& element, const std::string& detection,
                                    double x0, const std::string& extra) {
  return R"(
[analysis]
kind = "plane_strain"
element = ")" + element + R"("
geometric_nonlinearity = true
steps = 30
[[material]]
name = "m"
E = 1000.0
nu = 0.3
[[body]]
name = "base"
material = "m"
shape = { type = "rectangle", min = [0.0, 0.0], max = [6.0, 1.0] }
mesh = { size = 0.23 }
[[body]]
name = "slider"
material = "m"
shape = { type = "rectangle", min = [)" + std::to_string(x0) + R"(, 1.0], max = [)" +
         std::to_string(x0 + 1.0) + R"(, 1.5] }
mesh = { size = 0.17 }
[[support]]
on = { body = "base", edge = "bottom" }
fix = ["ux", "uy"]
[[support]]
on = { body = "slider", edge = "top" }
ux = 3.0
uy = -0.01
[[contact]]
slave = { body = "slider", edge = "bottom" }
master = { body = "base", edge = "top" }
detection = ")" + detection + R"("
)" + extra + R"(
[[probe]]
name = "fx"
on = { body = "slider", edge = "top" }
quantity = "reaction_x"
[[probe]]
name = "fy"
on = { body = "slider", edge = "top" }
quantity = "reaction_y"
)";
}

inline SceneRun run_scene(const core::Scene& scene, const std::string& method) {
  const core::Model model = core::build_model(scene);
  const constraints::ContactSet set(model, constraints::parse_contact_scene(scene, method), scene);
  SceneRun r;
  if (scene.analysis.geometric_nonlinearity) {
    nonlinear::StepperOptions o;
    o.steps = scene.analysis.steps;
    r.results = nonlinear::solve_geometric_nonlinear(model, scene.analysis, o, &r.trace, &set,
                                                     &r.report);
  } else {
    r.results = nonlinear::solve_linear_static(model, scene.analysis, &set, &r.report);
  }
  if (r.results.status == SolveStatus::kConverged)
    r.results.probes = core::evaluate_probes(scene, model, r.results);
  return r;
}

}  // namespace c2d::test
