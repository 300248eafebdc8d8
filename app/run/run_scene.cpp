#include "app/run/run_scene.hpp"

#include <chrono>
#include <cstdio>
#include <utility>

#include "app/report/summary.hpp"
#include "core/interrupt.hpp"
#include "core/writers.hpp"

namespace c2d::app {

namespace {

std::string cycle_line(const AdaptCycle& c) {
  char line[200];
  std::snprintf(line, sizeof line,
                "adapt %2d   %8d DOFs   xi_g %8.3g   max xi_e %8.3g   error %6.2f %%   %7.2f s\n",
                c.cycle, c.dofs, c.global_parameter, c.max_local, 100 * c.relative_error,
                c.seconds);
  return line;
}

/// The run's lines: to the caller and, once there is one, to the output folder's run.log.
class RunLines {
 public:
  explicit RunLines(const RunOptions& o) : o_(o) {}
  void attach(RunOutput* output) { output_ = output; }
  void phase(const std::string& text) {
    if (output_) output_->log(text + '\n');
    if (o_.progress) o_.progress(text);
  }
  void report(const std::string& text) {
    if (output_) output_->log(text);
    if (o_.report) o_.report(text);
  }

 private:
  const RunOptions& o_;
  RunOutput* output_ = nullptr;
};

/// The solve, once or adaptively; `output` (may be null) gets every step's or cycle's fields
/// as soon as they are solved.
RunResult solve(const core::Scene& scene, const RunOptions& o, RunOutput* output,
                RunLines& lines, AdaptRun& adapt) {
  RunResult result;
  const auto phase = [&](const std::string& line) { lines.phase(line); };
  if (scene.adapt.enabled) {
    adapt = solve_adaptive(scene, o.method, phase, [&](const AdaptCycle& c, const SceneRun& r) {
      if (output) output->write_cycle(c, r);
      lines.report(cycle_line(c));
    });
    result.run = std::move(adapt.last);
    result.cycles = adapt.cycles;
    return result;
  }
  StateCallback on_state;
  if (output)
    on_state = [output](const nonlinear::StepRecord& s, const core::Model& m,
                        const core::Results& r) { output->write_step(s, m, r); };
  result.run = solve_scene(scene, o.method, phase, on_state);
  return result;
}

/// The summary of a run that writes no folder: what summary.json would hold.
nlohmann::json summary_in_memory(const core::Scene& scene, SceneRun& run, const AdaptRun* adapt,
                                 RunOutput::Clock::time_point start) {
  run.results.time.total =
      std::chrono::duration<double>(RunOutput::Clock::now() - start).count();
  return run_summary(scene, run, adapt);
}

/// The closing lines: the summary as a reader takes it in, the adaptive loop's end, a chart
/// that could not be drawn.
void report_end(const core::Scene& scene, const RunResult& r, const AdaptRun& adapt,
                const std::string& dir, const std::string& files_dir, RunLines& lines) {
  lines.report(terminal_summary(r.summary, dir, files_dir));
  if (scene.adapt.enabled)
    lines.report(std::string(adapt.reached ? "adapt      " : "warning    adapt: ") + adapt.stop +
                 " (adapt.csv, cycle_NN.vtu)\n");
  if (!r.chart_error.empty()) lines.report("warning    chart not written: " + r.chart_error + "\n");
}

}  // namespace

bool RunResult::converged() const {
  return run && run->results.status == SolveStatus::kConverged;
}

RunResult run_scene(const core::Scene& scene, const RunOptions& o) {
  RunLines lines(o);
  AdaptRun adapt;
  if (o.out.empty()) {
    RunResult r = solve(scene, o, nullptr, lines, adapt);
    r.summary = summary_in_memory(scene, *r.run, scene.adapt.enabled ? &adapt : nullptr, o.start);
    return r;
  }
  RunOutput output(scene, o.out);
  output.log("reading " + scene.path + "\n");
  lines.attach(&output);
  if (o.on_output) o.on_output(output);
  try {
    RunResult r = solve(scene, o, &output, lines, adapt);
    lines.phase("writing results to " + output.dir());
    r.chart_error = output.write_results(*r.run, o.start);
    r.summary = output.write_summary(*r.run, scene.adapt.enabled ? &adapt : nullptr);
    report_end(scene, r, adapt, output.dir(), output.work_dir(), lines);
    core::check_interrupt();  // the last chance: an interrupted run puts nothing in place
    output.commit();
    return r;
  } catch (const core::WriteError& e) {
    // Named as the user named the folder: the work folder goes with `output`.
    throw output.in_output_folder(e);
  }
}

}  // namespace c2d::app
