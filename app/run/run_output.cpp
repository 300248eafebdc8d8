#include "app/run/run_output.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstring>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <future>
#include <iomanip>
#include <map>
#include <sstream>
#include <system_error>
#include <vector>

#include "app/output_folder.hpp"
#include "app/process.hpp"
#include "app/report/charts.hpp"
#include "app/report/run_tables.hpp"
#include "app/report/summary.hpp"
#include "core/writers.hpp"

namespace c2d::app {

namespace {

double seconds_since(RunOutput::Clock::time_point t) {
  return std::chrono::duration<double>(RunOutput::Clock::now() - t).count();
}

}  // namespace

RunOutput::RunOutput(const core::Scene& scene, std::string dir)
    : scene_(scene), target_(std::move(dir)) {
  namespace fs = std::filesystem;
  // The target must be a folder or creatable as one; the run itself goes to a sibling work
  // folder, swapped in by commit(), so the target never mixes two runs.
  refuse_file_as_folder(target_);
  std::vector<std::string> inputs{scene.path};
  for (const core::BodySpec& b : scene.bodies) inputs.push_back(b.msh_file);
  refuse_foreign_folder(target_, inputs);
  fs::path folder = fs::absolute(target_).lexically_normal();
  if (!folder.has_filename()) folder = folder.parent_path();  // "out/" names "out"
  // The folders this run creates above its target, removed again if it ends without a result.
  std::error_code ec;
  for (fs::path p = folder.parent_path(); !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
    created_parent_ = p.string();
    if (p == p.parent_path()) break;
  }
  create_output_folder(folder.parent_path().string());
  remove_stale_work_folders(folder);
  // A fresh work folder of this process's own: never one that exists (a user's folder of that
  // name, or another thread's run into the same target).
  run_id_ = std::to_string(::getpid()) + "-" +
            std::to_string(Clock::now().time_since_epoch().count());
  const std::string base = folder.string() + ".part." + std::to_string(::getpid());
  for (int k = 0; k < 1000 && dir_.empty(); ++k) {
    const std::string candidate = k == 0 ? base : base + "." + std::to_string(k);
    if (!fs::exists(candidate, ec) && create_work_folder(candidate)) dir_ = candidate;
  }
  // The work folder is this run's detail: a failure to create it names the target the user gave.
  if (dir_.empty())
    throw InputError(target_ + ": expected an output folder that can be created, found that "
                     "the folder beside it that a run writes into first cannot be");
  log_.open(dir_ + "/run.log");
}

void RunOutput::remove_stale_work_folders(const std::filesystem::path& folder) {
  // A run killed outright (SIGKILL, a crash) leaves its work folder TARGET.part.PID[.K] with
  // its marker; one whose process is gone belongs to nobody. Anything else of a similar name
  // (a user's results.part.99999) is not a work folder and stays.
  namespace fs = std::filesystem;
  const std::string prefix = folder.filename().string() + ".part.";
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(folder.parent_path(), ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) != 0 || !e.is_directory(ec)) continue;
    const long pid = work_folder_owner(e.path().string());
    if (pid <= 0 || pid == ::getpid()) continue;
    const bool alive = ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
    if (!alive) fs::remove_all(e.path(), ec);
  }
}

namespace {

// What the interrupt handler needs, prepared before it is armed: it may only call
// async-signal-safe functions (open, write, close, rename, _exit).
char g_work[4096], g_target[4096], g_aside[4096], g_summary[4096], g_marker[4096];
// The earlier run's files under its set-aside name, deepest first, each NUL-terminated: the
// handler unlinks them (and rmdirs the folders) so an interrupted run leaves one folder.
char g_doomed[1 << 16];
size_t g_doomed_size = 0;
// 0: no run folder yet (or the run is complete): the handler just exits; 1: a run's work
// folder is armed and the handler puts it in place with an "interrupted" summary.
volatile sig_atomic_t g_armed = 0;
const char kInterrupted[] =
    "{\n  \"status\": \"interrupted\",\n  \"message\": \"SIGINT or SIGTERM before the run finished; "
    "the files are those written until then\"\n}\n";

void say(const char* text, size_t size) {
  [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, text, size);
}

extern "C" void on_interrupt(int) {
  if (!g_armed) {
    const char note[] = "interrupted: no results written\n";
    say(note, sizeof note - 1);
    ::_exit(130);
  }
  const int fd = ::open(g_summary, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd >= 0) {
    [[maybe_unused]] const ssize_t n = ::write(fd, kInterrupted, sizeof kInterrupted - 1);
    ::close(fd);
  }
  ::unlink(g_marker);            // the folder becomes a run folder (its manifest is written)
  ::rename(g_target, g_aside);  // an earlier run's folder, if any, is set aside
  ::rename(g_work, g_target);
  for (size_t at = 0; at < g_doomed_size; at += std::strlen(g_doomed + at) + 1)
    ::unlink(g_doomed + at);
  ::rmdir(g_aside);
  const char note[] = "interrupted: partial results and summary.json in the output folder\n";
  say(note, sizeof note - 1);
  ::_exit(130);
}

void copy_path(char* to, const std::string& from) {
  std::snprintf(to, 4096, "%s", from.c_str());
}


}  // namespace

void install_interrupt_handler() { handle_interrupts(on_interrupt); }

void RunOutput::end_on_interrupt() {
  namespace fs = std::filesystem;
  g_armed = 0;
  copy_path(g_work, dir_);
  copy_path(g_target, target_);
  const std::string aside = dir_ + ".interrupted-aside";
  copy_path(g_aside, aside);
  copy_path(g_summary, dir_ + "/summary.json");
  copy_path(g_marker, dir_ + "/" + kWorkMarker);
  // The earlier run's files (those its manifest lists) as they will be named once set aside;
  // anything else keeps the set-aside folder in place.
  std::vector<std::string> doomed;
  std::error_code ec;
  if (fs::is_directory(target_, ec)) {
    for (const std::string& name : run_manifest_names(target_)) doomed.push_back(aside + "/" + name);
    doomed.push_back(aside + "/stdout.log");
    doomed.push_back(aside + "/" + kRunManifest);
  }
  g_doomed_size = 0;
  for (const std::string& d : doomed) {
    if (g_doomed_size + d.size() + 1 > sizeof g_doomed) break;  // the rest stays
    std::memcpy(g_doomed + g_doomed_size, d.c_str(), d.size() + 1);
    g_doomed_size += d.size() + 1;
  }
  write_run_manifest(dir_, run_id_, {"summary.json"});
  g_armed = 1;
  interrupt_armed_ = true;
}

RunOutput::~RunOutput() {
  if (interrupt_armed_) g_armed = 0;
  if (committed_) return;
  namespace fs = std::filesystem;
  std::error_code ec;  // a run that ended in an exception leaves nothing behind
  fs::remove_all(dir_, ec);
  if (created_parent_.empty()) return;
  // ... nor the folders it made above its target, where nothing else has appeared since.
  for (fs::path p = fs::path(dir_).parent_path(); fs::is_empty(p, ec) && !ec; p = p.parent_path()) {
    const bool last = p == fs::path(created_parent_);
    fs::remove(p, ec);
    if (last || ec) break;
  }
}

core::WriteError RunOutput::in_output_folder(const core::WriteError& e) const {
  const std::string work = dir_ + "/";
  const std::string name = e.path().rfind(work, 0) == 0 ? e.path().substr(work.size()) : e.path();
  return core::WriteError(e.path(), e.error_number(),
                          target_ + ": cannot write the run's " + name + ": " + e.reason() +
                              " (nothing of this run was kept)");
}

void RunOutput::commit() {
  namespace fs = std::filesystem;
  const InterruptsHeld held;  // an interrupt now waits until the folder is in place
  log_.close();
  std::error_code ec;
  write_run_manifest(dir_, run_id_);
  fs::remove(dir_ + "/" + kWorkMarker, ec);
  const std::string old = dir_ + ".old";
  const bool replaced = fs::exists(target_, ec);
  if (replaced) fs::rename(target_, old);
  fs::rename(dir_, target_);
  if (replaced) {
    // A study worker's log of this run, open as its stdout, moves with its inode into the
    // folder now in place (it was left behind in the folder set aside, with that folder).
    if (fs::is_regular_file(old + "/stdout.log", ec) && !fs::exists(target_ + "/stdout.log", ec))
      fs::rename(old + "/stdout.log", target_ + "/stdout.log", ec);
    // Only what the earlier run wrote; a folder with more stays. An empty one (the log was all
    // it held) goes.
    if (!remove_run_folder(old)) fs::remove(old, ec);
  }
  committed_ = true;
  if (interrupt_armed_) g_armed = 0;  // from here on the run is complete
}

void RunOutput::write_series(Series& files, const std::string& pvd, const char* pattern, int number,
                             double time, const core::Model& model, const core::Results& results) {
  if (!scene_.output_fields) return;
  char name[32];
  std::snprintf(name, sizeof name, pattern, number);
  core::write_file_atomic(dir_ + "/" + name, core::vtu_document(model, results, scene_.output_vtu));
  files.emplace_back(time, name);
  core::write_file_atomic(dir_ + "/" + pvd, core::pvd_document(files));
  if (interrupt_armed_) write_run_manifest(dir_, run_id_, {"summary.json"});
}

void RunOutput::write_step(const nonlinear::StepRecord& step, const core::Model& model,
                           const core::Results& results) {
  write_series(step_files_, "results.pvd", "step_%04d.vtu", step.step, step.load_factor, model,
               results);
}

void RunOutput::write_cycle(const AdaptCycle& cycle, const SceneRun& run) {
  write_series(cycle_files_, "adapt.pvd", "cycle_%02d.vtu", cycle.cycle, cycle.cycle, run.model,
               run.results);
  cycles_.push_back(cycle);
  core::write_file_atomic(dir_ + "/adapt.csv", adapt_csv(cycles_));
}

namespace {

/// steps.csv: one row per converged step (StepRow), the probes as the last columns.
std::string steps_csv(const SceneRun& run) {
  std::ostringstream os;
  os << std::setprecision(12);
  std::vector<const StepColumn*> columns;
  for (const StepColumn& c : step_columns())
    if (run.contact || !c.contact) columns.push_back(&c);
  const char* separator = "";
  for (const StepColumn* c : columns) os << separator << c->name, separator = ",";
  const auto& first = run.step_rows.empty() ? std::map<std::string, double>() : run.step_rows[0].probes;
  // A probe named as a fixed column keeps its name behind "probe_".
  for (const auto& [name, value] : first) {
    const bool clash = std::any_of(step_columns().begin(), step_columns().end(),
                                   [&](const StepColumn& c) { return name == c.name; });
    os << ',' << (clash ? "probe_" : "") << name;
  }
  os << '\n';
  for (const StepRow& r : run.step_rows) {
    separator = "";
    for (const StepColumn* c : columns) os << separator << c->value(r), separator = ",";
    for (const auto& [name, value] : r.probes) os << ',' << value;
    os << '\n';
  }
  return os.str();
}

}  // namespace

void RunOutput::write_tables(const SceneRun& run) {
  const core::Results& results = run.results;
  core::write_file_atomic(dir_ + "/steps.csv", steps_csv(run));
  if (scene_.output_fields)
    core::write_file_atomic(dir_ + "/nodes.csv", core::nodes_csv(run.model, results));
  // A load-stepped scene's tables go by step; a one-step linear run's trace is its method's
  // iterations, and its contact table the one state.
  const bool stepped = scene_.analysis.geometric_nonlinearity || run.steps.size() > 1;
  if (run.contact) core::write_file_atomic(dir_ + "/contact.csv", contact_csv(run.contact_report));
  if (run.contact && !run.contact_report.equality_names.empty())
    core::write_file_atomic(dir_ + "/constraints.csv", constraints_csv(run.contact_report));
  if (stepped)
    core::write_file_atomic(dir_ + "/trace.csv", newton_trace_csv(run.steps));
  else if (run.contact)
    core::write_file_atomic(dir_ + "/trace.csv", trace_csv(run.contact_report));
  if (run.contact)
    core::write_file_atomic(
        dir_ + "/contact_steps.csv",
        stepped ? contact_steps_csv(run.steps)
                : contact_steps_csv(run.contact_report, results.status == SolveStatus::kConverged));
}

std::string RunOutput::write_charts(const SceneRun& run) {
  if (run.results.status != SolveStatus::kConverged || !scene_.output_charts) return "";
  // The charts are independent (each its own gnuplot and files; all read the run, none writes
  // it), so they are drawn side by side: a frictional run's three took 0.6 s one after another.
  // Every thread is joined here; the first chart's error in this order is the one reported.
  std::vector<std::future<std::string>> charts;
  charts.push_back(std::async(std::launch::async, [&] {
    return chart_deformed_mesh(dir_, run.model, run.results, scene_.units,
                               scene_.analysis.geometric_nonlinearity);
  }));
  if (run.contact && run.contact_report.has_surface)
    charts.push_back(std::async(std::launch::async, [&] {
      return chart_contact_pressure(dir_, run.contact_report, scene_);
    }));
  if (run.contact && !step_files_.empty())
    charts.push_back(std::async(std::launch::async, [&] {
      return chart_contact_zone(dir_, dir_ + "/" + step_files_.back().second, run.contact_report,
                                run.contact_spec.obstacles, run.model.mesh.nodes, run.results,
                                scene_.units);
    }));
  std::string error;
  std::exception_ptr failure;
  for (auto& chart : charts) {
    try {
      const std::string e = chart.get();
      if (error.empty()) error = e;
    } catch (...) {
      if (!failure) failure = std::current_exception();
    }
  }
  if (failure) std::rethrow_exception(failure);
  return error;
}

std::string RunOutput::write_results(SceneRun& run, Clock::time_point start) {
  const auto t_out = Clock::now();
  core::Results& results = run.results;
  const bool ok = results.status == SolveStatus::kConverged;
  if ((step_files_.empty() || !ok) && scene_.output_fields) {
    // A linear run is one step; a failed load-stepped run adds its last converged state.
    const double load_factor = step_files_.empty() ? 1.0 : results.globals["load_factor"];
    write_series(step_files_, "results.pvd", "step_%04d.vtu",
                 static_cast<int>(step_files_.size()) + 1, load_factor, run.model, results);
  }
  write_tables(run);
  const std::string chart_error = write_charts(run);
  results.time.output +=
      seconds_since(t_out);  // per-step VTUs written during the solve, then the rest
  results.time.total = seconds_since(start);
  return chart_error;
}

nlohmann::json run_summary(const core::Scene& scene, const SceneRun& run, const AdaptRun* adapt) {
  const SummaryParts parts{scene,
                           &run.model,
                           &run.results,
                           run_status(run.results),
                           run.contact ? &run.contact_report : nullptr,
                           run.steps.empty() ? nullptr : &run.steps,
                           adapt ? adapt_summary(scene.adapt, *adapt) : nlohmann::json()};
  return make_summary(parts);
}

nlohmann::json RunOutput::write_summary(const SceneRun& run, const AdaptRun* adapt) {
  const nlohmann::json summary = run_summary(scene_, run, adapt);
  core::write_file_atomic(dir_ + "/summary.json", summary.dump(2) + "\n");
  return summary;
}

void RunOutput::log(const std::string& text) {
  log_ << text << std::flush;
}

}  // namespace c2d::app
