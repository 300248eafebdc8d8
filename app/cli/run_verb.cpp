// `contact2d run`: solve a scene (once, or adaptively) and write its files through RunOutput.
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>

#include "app/cli/verbs.hpp"
#include "app/report/summary.hpp"
#include "app/run/adapt.hpp"
#include "app/run/run_output.hpp"
#include "core/writers.hpp"

namespace c2d::app {

namespace {

/// Progress and log: lines go to the terminal (unless quiet) and to run.log.
class Reporter {
 public:
  explicit Reporter(bool quiet) : quiet_(quiet), tty_(::isatty(STDERR_FILENO)) {}
  void phase(const std::string& what) {
    write_log(what + '\n');
    if (!quiet_ && tty_) std::cerr << "  .. " << what << std::endl;
  }
  void line(const std::string& text) {
    write_log(text);
    if (!quiet_) std::cout << text << std::flush;
  }
  /// From now on run.log gets every line as it is printed (the earlier ones first).
  void attach(RunOutput& output) {
    output_ = &output;
    output.log(early_.str());
  }

 private:
  void write_log(const std::string& text) {
    if (output_) output_->log(text);
    else early_ << text;
  }
  bool quiet_, tty_;
  std::ostringstream early_;
  RunOutput* output_ = nullptr;
};

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

std::string cycle_line(const AdaptCycle& c) {
  char line[200];
  std::snprintf(line, sizeof line,
                "adapt %2d   %8d DOFs   xi_g %8.3g   max xi_e %8.3g   error %6.2f %%   %7.2f s\n",
                c.cycle, c.dofs, c.global_parameter, c.max_local, 100 * c.relative_error,
                c.seconds);
  return line;
}

/// The run once its output folder is set up: solve, write, commit.
int run_into(const Options& o, const core::Scene& scene, RunOutput& output, Reporter& rep,
             RunOutput::Clock::time_point t0) {
  rep.attach(output);
  output.end_on_interrupt();
  const auto phase = [&](const std::string& line) { rep.phase(line); };
  std::unique_ptr<SceneRun> solved;
  AdaptRun adapt;
  if (scene.adapt.enabled) {
    // Every cycle leaves its mesh and fields and a row of adapt.csv as soon as it is solved.
    adapt = solve_adaptive(scene, o.method, phase, [&](const AdaptCycle& c, const SceneRun& r) {
      output.write_cycle(c, r);
      rep.line(cycle_line(c));
    });
    solved = std::move(adapt.last);
  } else {
    // A load-stepped run leaves every converged step as soon as it is solved.
    solved = solve_scene(scene, o.method, phase,
                         [&](const nonlinear::StepRecord& s, const core::Model& m,
                             const core::Results& r) { output.write_step(s, m, r); });
  }
  rep.phase("writing results to " + output.dir());
  const std::string chart_error = output.write_results(*solved, t0);
  const nlohmann::json summary =
      output.write_summary(*solved, scene.adapt.enabled ? &adapt : nullptr);
  rep.line(terminal_summary(summary, output.dir(), output.work_dir()));
  if (scene.adapt.enabled)
    rep.line(std::string(adapt.reached ? "adapt      " : "warning    adapt: ") + adapt.stop +
             " (adapt.csv, cycle_NN.vtu)\n");
  if (!chart_error.empty()) rep.line("warning    chart not written: " + chart_error + "\n");
  output.commit();
  return solved->results.status == SolveStatus::kConverged ? kExitOk : kExitSolveFailed;
}

}  // namespace

int cmd_run(const Options& o) {
  install_interrupt_handler();
  const auto t0 = RunOutput::Clock::now();
  Reporter rep(o.quiet);
  rep.phase("reading " + o.scene);
  const core::Scene scene = load_run_scene(o);
  RunOutput output(scene, default_out(o, scene));
  try {
    return run_into(o, scene, output, rep, t0);
  } catch (const core::WriteError& e) {
    throw output.in_output_folder(e);
  }
}

}  // namespace c2d::app
