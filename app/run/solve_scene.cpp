#include "app/run/solve_scene.hpp"

#include <cstdio>

#include "core/errors.hpp"
#include "core/interrupt.hpp"
#include "core/probes.hpp"
#include "nonlinear/load_stepper.hpp"

namespace c2d::app {

namespace {

StepRow step_row(const core::Scene& scene, const core::Model& model,
                 const nonlinear::StepRecord& s, const core::Results& r) {
  StepRow row;
  row.step = s.step;
  row.load_factor = s.load_factor;
  row.newton_iterations = s.newton.iterations;
  row.factorizations = s.factorizations;
  for (int dof = 0; dof < model.dofs.num_dofs(); ++dof)
    if (model.dofs.is_constrained(dof)) (dof % 2 ? row.reaction_y : row.reaction_x) += r.reaction[dof];
  row.active_nodes = s.contact_state.active_nodes;
  row.contact_force = s.contact_state.total_force;
  row.tangential_force = s.contact_state.tangent_force;
  row.probes = core::evaluate_probes(scene, model, r);
  return row;
}

}  // namespace

std::unique_ptr<SceneRun> solve_scene(const core::Scene& scene, const std::string& method,
                                      const std::function<void(const std::string&)>& progress,
                                      const StateCallback& on_state) {
  auto say = [&](const std::string& text) {
    core::check_interrupt();
    if (progress) progress(text);
  };
  auto run = std::make_unique<SceneRun>();
  say("meshing " + std::to_string(scene.bodies.size()) + " bod" +
      (scene.bodies.size() == 1 ? "y" : "ies"));
  run->contact_spec = constraints::parse_contact_scene(scene, method);
  run->model = core::build_model(scene);
  const core::Model& model = run->model;
  if (!run->contact_spec.empty() || !model.plates.empty() ||
      (scene.explicit_model && !scene.explicit_model->gaps.empty()))
    run->contact = std::make_unique<constraints::ContactSet>(model, run->contact_spec, scene);
  if (!method.empty() && !run->contact)
    throw InputError("--method " + method + ": the scene has no [[contact]] to enforce");
  say("solving " + std::to_string(model.dofs.num_free()) + " equations" +
      (run->contact ? " with " + run->contact_spec.options.method + " contact (" +
                          std::to_string(run->contact->pairs().num_slave_nodes()) + " slave nodes)"
                    : std::string()));
  // One driver: a linear analysis is the small-strain system taking its load in its steps (one
  // by default), a geometric-nonlinear one the finite-strain system in its load steps.
  nonlinear::StepperOptions so;
  so.steps = scene.analysis.steps;
  so.newton.max_iterations = scene.analysis.max_newton_iterations;
  const bool stepped = scene.analysis.geometric_nonlinearity || scene.analysis.steps > 1;
  if (stepped)
    so.on_step = [&](const nonlinear::StepRecord& s) {
      char line[200];
      std::snprintf(line, sizeof line, "step %d  lambda %.4g  %s in %d Newton iterations", s.step,
                    s.load_factor, to_string(s.newton.status), s.newton.iterations);
      std::string text = line;
      if (!s.contact.empty()) {
        std::snprintf(line, sizeof line, ", %zu outer, %d active (+%d -%d)", s.contact.size(),
                      s.contact.back().active, s.contact.front().entering,
                      s.contact.front().leaving);
        text += line;
      }
      if (s.attempt > 0) text += " (after a cutback)";
      if (!s.fallback.empty())
        text += " (" + s.fallback_reason + ": finished by " + s.fallback + ")";
      say(text);
    };
  so.on_state = [&](const nonlinear::StepRecord& s, const core::Results& r) {
    run->step_rows.push_back(step_row(scene, model, s, r));
    if (on_state) on_state(s, model, r);
  };
  run->results = nonlinear::solve_load_steps(model, scene.analysis, so, &run->steps,
                                             run->contact.get(), &run->contact_report);
  if (run->results.status == SolveStatus::kConverged)
    run->results.probes = core::evaluate_probes(scene, model, run->results);
  return run;
}

const std::vector<StepColumn>& step_columns() {
  static const std::vector<StepColumn> columns = {
      {"step", [](const StepRow& r) -> double { return r.step; }, false},
      {"load_factor", [](const StepRow& r) { return r.load_factor; }, false},
      {"newton_iterations", [](const StepRow& r) -> double { return r.newton_iterations; }, false},
      {"factorizations", [](const StepRow& r) -> double { return r.factorizations; }, false},
      {"reaction_x", [](const StepRow& r) { return r.reaction_x; }, false},
      {"reaction_y", [](const StepRow& r) { return r.reaction_y; }, false},
      {"contact_active_nodes", [](const StepRow& r) -> double { return r.active_nodes; }, true},
      {"contact_normal_force", [](const StepRow& r) { return r.contact_force; }, true},
      {"contact_tangential_force", [](const StepRow& r) { return r.tangential_force; }, true},
  };
  return columns;
}

}  // namespace c2d::app
