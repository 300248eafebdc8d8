// summary.json and the short terminal summary of a run.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "constraints/contact_set.hpp"
#include "core/model.hpp"
#include "core/results.hpp"
#include "core/scene.hpp"
#include "nonlinear/load_stepper.hpp"

namespace c2d::app {

/// What a run's summary is made of.
struct SummaryParts {
  const core::Scene& scene;
  const core::Model* model = nullptr;
  const core::Results* results = nullptr;
  std::string status;                                         ///< see run_status
  const constraints::ContactReport* contact = nullptr;        ///< contact runs
  const std::vector<nonlinear::StepRecord>* steps = nullptr;  ///< load-stepped runs
  nlohmann::json adapt;                                       ///< adaptive runs, else null
};

/// "converged", or "failed: " with the status (unless a plain failure) and the message.
std::string run_status(const core::Results& results);

/// The stable summary keys (DESIGN §4): status, method, mesh, time_s, steps, newton_iterations,
/// contact, error, probes; plus solver details, the scene's reference, the load stepping
/// (load_factor) and the adaptive cycles when there were any.
nlohmann::json make_summary(const SummaryParts& parts);

/// A few human lines for the terminal, naming `out_dir` and the files of the run found in
/// `files_dir` (the folder they are in now; default `out_dir`).
std::string terminal_summary(const nlohmann::json& summary, const std::string& out_dir,
                             const std::string& files_dir = "");

}  // namespace c2d::app
