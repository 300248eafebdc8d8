// The verbs of contact2d: each takes the parsed options and returns the exit code; bad input
// throws InputError (exit 2, printed by main).
#pragma once

#include <string>

#include "app/cli/options.hpp"
#include "core/scene.hpp"

namespace c2d::app {

/// The output folder: --out, else the scene's output.dir, else out/<scene file stem>.
std::string default_out(const Options& o, const core::Scene& scene);

/// `run SCENE`: solve and write the run's files (RunOutput), print the summary.
int cmd_run(const Options& o);
/// `mesh SCENE`: mesh.vtu and mesh figures.
int cmd_mesh(const Options& o);
/// `info SCENE`: what the scene defines and how many nodes each selection picks.
int cmd_info(const Options& o);
/// `trace OUTDIR`: charts of a finished run's trace.
int cmd_trace(const Options& o);
/// `plot OUTDIR`: field pictures of a finished run.
int cmd_plot(const Options& o);
/// `compare SCENE`: every method over refinement levels.
int cmd_compare(const Options& o);
/// `sweep SCENE`: one scene key over a range.
int cmd_sweep(const Options& o);
/// `calibrate SCENE`: scene parameters fitted to measured probe values.
int cmd_calibrate(const Options& o);
/// `bench`: the benchmark ladder (takes no scene).
int cmd_bench(const Options& o);
/// `merge DIR`: a study's report from the case folders that have finished.
int cmd_merge(const Options& o);

}  // namespace c2d::app
