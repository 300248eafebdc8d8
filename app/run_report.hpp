// summary.json and the short terminal summary of a run.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "core/model.hpp"
#include "core/results.hpp"
#include "core/scene.hpp"

namespace c2d::app {

/// The stable summary keys (DESIGN §4): status, method, mesh, time_s, steps, newton_iterations,
/// contact, error, probes; plus solver details and the scene's reference.
nlohmann::json make_summary(const core::Scene& scene, const core::Model* model,
                            const core::Results* results, const std::string& status);

/// A few human lines for the terminal.
std::string terminal_summary(const nlohmann::json& summary, const std::string& out_dir);

}  // namespace c2d::app
