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
#include "nonlinear/linear_static.hpp"
#include "nonlinear/load_stepper.hpp"

namespace c2d::test {

struct SceneRun {
  core::Results results;
  constraints::ContactReport report;
  std::vector<nonlinear::StepRecord> trace;  ///< load-stepped runs
};

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
