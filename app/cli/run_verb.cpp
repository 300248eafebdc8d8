// `contact2d run`: a scene run through the library's entry point (app/run/run_scene.hpp), its
// progress on the terminal.
#include <unistd.h>

#include <iostream>

#include "app/cli/verbs.hpp"
#include "app/run/run_scene.hpp"

namespace c2d::app {

namespace {

/// The scene with --set and, for --adapt, the [adapt] overrides applied.
core::Scene load_run_scene(const Options& o) {
  core::Scene scene = core::load_scene(o.scene, o.sets);
  if (o.adapt && scene.explicit_model) {
    scene.adapt.enabled = true;  // --set does not apply to legacy files; solve_adaptive refuses it
  } else if (o.adapt) {
    std::vector<std::string> sets = o.sets;
    sets.insert(sets.end(), o.adapt_sets.begin(), o.adapt_sets.end());
    scene = core::load_scene(o.scene, sets);
  }
  return scene;
}

}  // namespace

int cmd_run(const Options& o) {
  install_interrupt_handler();
  RunOptions run;
  run.start = RunOutput::Clock::now();
  const bool tty = ::isatty(STDERR_FILENO);
  // Phases on a terminal only (a log or a job's output keeps the lines that matter).
  if (!o.quiet && tty)
    run.progress = [](const std::string& what) { std::cerr << "  .. " << what << std::endl; };
  if (!o.quiet) run.report = [](const std::string& text) { std::cout << text << std::flush; };
  run.on_output = [](RunOutput& output) { output.end_on_interrupt(); };
  if (run.progress) run.progress("reading " + o.scene);
  const core::Scene scene = load_run_scene(o);
  run.method = o.method;
  run.out = default_out(o, scene);
  return run_scene(scene, run).converged() ? kExitOk : kExitSolveFailed;
}

}  // namespace c2d::app
