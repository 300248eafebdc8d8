// summary.json and the short terminal summary of a run.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "constraints/contact_set.hpp"
#include "core/model.hpp"
#include "core/results.hpp"
#include "core/scene.hpp"
#include "nonlinear/load_stepper.hpp"

namespace c2d::app {

/// The stable summary keys (DESIGN §4): status, method, mesh, time_s, steps, newton_iterations,
/// contact, error, probes; plus solver details and the scene's reference.
nlohmann::json make_summary(const core::Scene& scene, const core::Model* model,
                            const core::Results* results, const std::string& status,
                            const constraints::ContactReport* contact = nullptr);

/// One row per slave node: node, x, y, gap, force, pressure, active, penalty.
std::string contact_csv(const constraints::ContactReport& contact);

/// One row per backend iteration (DESIGN §4 columns; one load step in a linear analysis).
std::string trace_csv(const constraints::ContactReport& contact);

/// A few human lines for the terminal.
std::string terminal_summary(const nlohmann::json& summary, const std::string& out_dir);

/// One row per Newton iteration of every load step attempt (DESIGN §4 columns).
std::string newton_trace_csv(const std::vector<nonlinear::StepRecord>& steps);

/// contact_steps.csv: per converged load step and slave node: step, load_factor, node, x, y
/// (reference position), gap, force, pressure, active.
std::string contact_steps_csv(const std::vector<nonlinear::StepRecord>& steps);

}  // namespace c2d::app
