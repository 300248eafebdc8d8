// One scene from model to results: mesh, contact set, the linear or load-stepped solve, probes.
// Shared by `run` and by the studies that solve in-process (calibration).
#pragma once

#include <functional>
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

struct SceneRun {
  core::Model model;
  std::unique_ptr<constraints::ContactSet> contact;  ///< refers to `model`; null without contact
  constraints::ContactSceneSpec contact_spec;
  core::Results results;  ///< probes evaluated when converged
  constraints::ContactReport contact_report;
  std::vector<nonlinear::StepRecord> steps;  ///< load-stepped analyses only
};

/// Builds and solves the scene; `method` overrides the contact method (empty: the scene's).
/// `progress` receives one line per phase and load step (may be empty). Throws InputError for
/// bad input (including a --method on a scene without contact); numerical failures are in
/// results.status.
/// `on_state` (load-stepped analyses only) receives every converged step's fields.
using StateCallback =
    std::function<void(const nonlinear::StepRecord&, const core::Model&, const core::Results&)>;
std::unique_ptr<SceneRun> solve_scene(const core::Scene& scene, const std::string& method,
                                      const std::function<void(const std::string&)>& progress,
                                      const StateCallback& on_state = {});

}  // namespace c2d::app
