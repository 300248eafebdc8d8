// One run of a scene, end to end: the entry point that the command line (`contact2d run`), the
// Python module (contact2d.run) and C++ programs share. It solves the scene (once, or
// adaptively when its [adapt] asks), builds summary.json's content and, when an output folder
// is named, writes the run's files as the solve goes and puts them in place at the end.
#pragma once

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/run/adapt.hpp"
#include "app/run/run_output.hpp"
#include "app/run/solve_scene.hpp"
#include "core/scene.hpp"

namespace c2d::app {

struct RunOptions {
  /// The contact method; empty: the scene's own.
  std::string method;
  /// The output folder; empty: nothing is written (the result is returned only).
  std::string out;
  /// One line per phase, load step and adaptive cycle as the run goes; may be empty.
  std::function<void(const std::string&)> progress;
  /// The lines that end a run for its reader (the summary, warnings); may be empty. They and
  /// the progress lines are also the output folder's run.log.
  std::function<void(const std::string&)> report;
  /// Called once the output folder is set up, before the solve (a program arms its interrupt
  /// handler on it: RunOutput::end_on_interrupt); may be empty.
  std::function<void(RunOutput&)> on_output;
  /// Where the run's total time counts from (a program: its start, before reading the scene).
  RunOutput::Clock::time_point start = RunOutput::Clock::now();
};

struct RunResult {
  std::unique_ptr<SceneRun> run;  ///< the solved model, fields, contact report and steps
  nlohmann::json summary;         ///< summary.json's content
  std::vector<AdaptCycle> cycles; ///< adaptive runs: every cycle (the last one's run is `run`)
  std::string chart_error;        ///< why a chart was not written ("" if none, or no folder)
  bool converged() const;
};

/// Runs `scene` as options say. Throws InputError for bad input (a --method on a scene without
/// contact, an output folder that cannot be used), core::WriteError naming the output folder
/// for a file that cannot be written (the folder is then left as it was), and core::Interrupted
/// when the caller's poll (core/interrupt.hpp) asks to stop (nothing is put in place).
/// Numerical failures are the result's status, never exceptions.
RunResult run_scene(const core::Scene& scene, const RunOptions& options = {});

}  // namespace c2d::app
