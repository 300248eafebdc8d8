// One scene from model to results: mesh, contact set, the linear or load-stepped solve, probes.
// Shared by `run` and by the studies that solve in-process (calibration).
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "constraints/contact_scene.hpp"
#include "constraints/contact_set.hpp"
#include "core/model.hpp"
#include "core/results.hpp"
#include "core/scene.hpp"
#include "nonlinear/load_stepper.hpp"

namespace c2d::app {

/// One converged load step as steps.csv and Python's fields["steps"] give it: the step's work,
/// the support reactions summed, the contact's totals and every [[probe]] at that state.
struct StepRow {
  int step = 0;
  double load_factor = 0.0;
  int newton_iterations = 0, factorizations = 0;  ///< of the converged attempt
  double reaction_x = 0.0, reaction_y = 0.0;      ///< Σ over the supported DOFs
  int active_nodes = 0;                           ///< with contact
  double contact_force = 0.0, tangential_force = 0.0;
  std::map<std::string, double> probes;
};

/// A fixed column of steps.csv and of Python's fields["steps"]: its name, its value in a row,
/// and whether only a run with contact has it.
struct StepColumn {
  const char* name;
  double (*value)(const StepRow&);
  bool contact;
};

/// The fixed columns in steps.csv's order; the probes follow them.
const std::vector<StepColumn>& step_columns();

struct SceneRun {
  core::Model model;
  std::unique_ptr<constraints::ContactSet> contact;  ///< refers to `model`; null without contact
  constraints::ContactSceneSpec contact_spec;
  core::Results results;  ///< probes evaluated when converged
  constraints::ContactReport contact_report;
  std::vector<nonlinear::StepRecord> steps;  ///< every attempt of every load step
  std::vector<StepRow> step_rows;            ///< every converged step
};

/// Builds and solves the scene; `method` overrides the contact method (empty: the scene's).
/// `progress` receives one line per phase and load step (may be empty). Throws InputError for
/// bad input (including a --method on a scene without contact); numerical failures are in
/// results.status.
/// `on_state` receives every converged step's fields (a linear run's one step included).
using StateCallback =
    std::function<void(const nonlinear::StepRecord&, const core::Model&, const core::Results&)>;
std::unique_ptr<SceneRun> solve_scene(const core::Scene& scene, const std::string& method,
                                      const std::function<void(const std::string&)>& progress,
                                      const StateCallback& on_state = {});

}  // namespace c2d::app
