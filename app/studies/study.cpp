#include "app/studies/study.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <mutex>
#include <sstream>
#include <thread>

#include "app/output_folder.hpp"
#include "app/process.hpp"
#include "app/report/json_file.hpp"
#include "core/writers.hpp"

namespace fs = std::filesystem;

namespace c2d::app {

namespace {

/// The summary.json a case stopped at the time limit left in `dir` (a `contact2d run` ended by
/// SIGTERM writes status "interrupted") says "timeout" and the limit instead, so that a merge
/// of the study reports what the study did. A summary older than the case (an earlier run's,
/// when SIGKILL left the folder as it was) or of another status is left alone.
void mark_timed_out(const std::string& dir, double limit_s, fs::file_time_type started) {
  const std::string path = dir + "/summary.json";
  std::error_code ec;
  const fs::file_time_type written = fs::last_write_time(path, ec);
  // File times come from a coarser clock than now(): a second's margin.
  if (ec || written < started - std::chrono::seconds(1)) return;
  JsonFileRead r = try_read_json_file(path);
  if (!r.ok() || !r.value.is_object() || r.value.value("status", nlohmann::json()) != "interrupted")
    return;
  r.value["status"] = "timeout";
  r.value["message"] = "stopped by the study after " + csv_number(limit_s) +
                       " s, its per-case time limit (--case-timeout); the files are those "
                       "written until then";
  r.value["time_limit_s"] = limit_s;
  core::write_file_atomic(path, r.value.dump(2) + "\n");
}

CaseOutcome run_one(const std::string& exe, const StudyCase& c, const std::string& study_dir,
                    const std::vector<std::string>& env, double limit_s) {
  const std::string dir = study_dir + "/" + c.folder;
  fs::create_directories(dir);
  const fs::file_time_type started = fs::file_time_type::clock::now();
  const auto t0 = std::chrono::steady_clock::now();
  const ProcessOutcome run = run_process(exe, run_arguments(c, dir), dir + "/stdout.log", env, {},
                                         {limit_s, kCaseKillGrace});
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (run.timed_out) mark_timed_out(dir, limit_s, started);
  CaseOutcome out = read_case_folder(dir);
  out.exit_code = run.started ? run.exit_code : -1;
  out.timed_out = run.timed_out;
  if (run.timed_out) out.time_limit_s = limit_s;
  out.wall_seconds = wall;
  if (run.started) out.peak_rss_mb = run.peak_rss_mb;
  return out;
}

/// The thread-count variables a case's process gets (those the user set are left as set).
std::vector<std::string> case_environment(int jobs) {
  std::vector<std::string> env;
  const std::string threads = std::to_string(threads_per_case(jobs));
  for (const char* name : {"OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS"})
    if (!std::getenv(name)) env.push_back(std::string(name) + "=" + threads);
  return env;
}

/// A time limit for the reports: "1800 s", or "unknown" (a merged case without one).
std::string limit_text(double seconds) {
  return std::isfinite(seconds) ? csv_number(seconds) + " s" : "unknown";
}

/// The values of a case's summary.json that the studies read as numbers (or null, which a run
/// writes for a figure it has not got), by key path, separated by spaces.
constexpr const char* kSummaryNumbers =
    "mesh.dofs newton_iterations time_s.mesh time_s.assemble time_s.solve time_s.total "
    "time_s.recovery time_s.output contact.iterations contact.pivot_ratio contact.penalty_max "
    "contact.stiffness_max contact.p_max contact.length contact.total_force "
    "contact.max_penetration contact.detection_seconds contact.friction.stick_length "
    "contact.friction.tangential_force error.relative_error reference.relative_error.p_max "
    "reference.relative_error.contact_length reference.relative_error.stick_length "
    "reference.relative_error.shear_profile_l2 reference.relative_error.pressure_profile_l2 "
    "reference.relative_error.pressure_profile_inner_l2 "
    "reference.relative_error.tip_uy reference.relative_error.a_uy process.wall_s "
    "process.peak_rss_mb solver.numeric_factorizations solver.symbolic_analyses solver.symbolic_s "
    "solver.numeric_s solver.triangular_solve_s time_limit_s";

/// Why the value at the dotted `path` of `s` is not a number, null or absent ("" when it is);
/// a section on the way must be an object (or null).
std::string number_problem(const nlohmann::json& s, const std::string& path) {
  const nlohmann::json* node = &s;
  for (size_t start = 0; start <= path.size();) {
    const size_t dot = std::min(path.find('.', start), path.size());
    const std::string key = path.substr(start, dot - start);
    const auto it = node->find(key);
    if (it == node->end() || it->is_null()) return "";
    node = &*it;
    start = dot + 1;
    const bool last = dot == path.size();
    if (!last && !node->is_object())
      return path.substr(0, dot) + ": expected an object, found " + shown_json(*node);
    if (last && !node->is_number()) return path + ": expected a number, found " + shown_json(*node);
  }
  return "";
}

/// Why `s` cannot be read as a run's summary ("" when it can): the type of each value read.
std::string summary_problem(const nlohmann::json& s) {
  if (!s.is_object()) return "expected an object, found " + shown_json(s);
  if (s.contains("status") && !s["status"].is_string())
    return "status: expected a string, found " + shown_json(s["status"]);
  for (const char* key : {"method", "units"})
    if (s.contains(key) && !s[key].is_string() && !s[key].is_null())
      return std::string(key) + ": expected a string or null, found " + shown_json(s[key]);
  std::istringstream paths(kSummaryNumbers);
  for (std::string path; paths >> path;) {
    const std::string problem = number_problem(s, path);
    if (!problem.empty()) return problem;
  }
  return "";
}

}  // namespace

std::vector<std::string> run_arguments(const StudyCase& c, const std::string& out_dir) {
  std::vector<std::string> args{"run"};
  args.insert(args.end(), c.args.begin(), c.args.end());
  args.insert(args.end(), {"--out", out_dir, "--quiet"});
  return args;
}

std::string this_executable() { return fs::read_symlink("/proc/self/exe").string(); }

CaseOutcome read_case_folder(const std::string& dir) {
  CaseOutcome out;
  const std::string path = dir + "/summary.json";
  std::error_code ec;
  if (fs::status(path, ec).type() == fs::file_type::not_found) return out;
  JsonFileRead r = try_read_json_file(path);
  if (r.ok()) r.error = summary_problem(r.value);
  if (!r.ok()) {
    out.malformed = r.error;
    std::replace(out.malformed.begin(), out.malformed.end(), '|', '/');  // a markdown cell
    return out;
  }
  out.summary = std::move(r.value);
  out.has_summary = true;
  out.exit_code = out.summary.value("status", std::string()) == "converged" ? 0 : 1;
  return out;
}

std::vector<size_t> read_finished_cases(
    const std::vector<StudyCase>& cases, const std::string& study_dir,
    const std::function<void(size_t, const CaseOutcome&)>& on_read) {
  std::vector<size_t> missing;
  for (size_t i = 0; i < cases.size(); ++i) {
    const CaseOutcome outcome = read_case_folder(study_dir + "/" + cases[i].folder);
    if (outcome.has_summary || !outcome.malformed.empty())
      on_read(i, outcome);
    else
      missing.push_back(i);
  }
  return missing;
}

std::string missing_cases_md(const std::vector<StudyCase>& cases,
                             const std::vector<size_t>& missing) {
  if (missing.empty()) return "";
  std::ostringstream md;
  md << "## Missing cases\n\n"
     << missing.size() << " of " << cases.size()
     << " cases have no summary.json yet (not run, still running, or crashed); the table and "
        "the verdict are of the others. Each is one line of jobs.txt:\n\n"
        "| case folder | jobs.txt line |\n|---|---|\n";
  for (size_t i : missing) md << "| " << cases[i].folder << " | " << i + 1 << " |\n";
  return md.str() + "\n";
}

std::string missing_cases_text(const std::vector<StudyCase>& cases,
                               const std::vector<size_t>& missing) {
  if (missing.empty()) return "";
  std::ostringstream os, lines, array;
  for (size_t k = 0; k < missing.size(); ++k) {
    const size_t line = missing[k] + 1;
    os << "missing    " << cases[missing[k]].folder << " (no summary.json; jobs.txt line " << line
       << ")\n";
    lines << (k ? ";" : "") << line << "p";
    array << (k ? "," : "") << line;
  }
  os << "missing    " << missing.size() << " of " << cases.size()
     << " cases; to run them again from the study folder: sed -n '" << lines.str()
     << "' jobs.txt | parallel, or sbatch --array=" << array.str()
     << " slurm.sh; then merge again\n\n";
  return os.str();
}

std::string timed_out_cases_md(const std::vector<StudyCase>& cases,
                               const std::vector<const RunFigures*>& rows) {
  std::ostringstream table;
  size_t n = 0;
  for (size_t i = 0; i < cases.size() && i < rows.size(); ++i)
    if (rows[i]->timed_out())
      ++n, table << "| " << cases[i].folder << " | " << limit_text(rows[i]->time_limit_s) << " | "
                 << i + 1 << " |\n";
  if (n == 0) return "";
  return "## Timed out\n\n" + std::to_string(n) + " of " + std::to_string(cases.size()) +
         " cases did not finish within the per-case time limit (--case-timeout) and were "
         "stopped: SIGTERM to the case's processes, SIGKILL " +
         seconds_text(kCaseKillGrace) +
         " later if any were left. Their rows say `timeout`; the study went on with the "
         "others. A case folder holds what its run wrote until then.\n\n"
         "| case folder | limit | jobs.txt line |\n|---|---|---|\n" +
         table.str() + "\n";
}

std::string timed_out_cases_text(const std::vector<StudyCase>& cases,
                                 const std::vector<const RunFigures*>& rows) {
  std::ostringstream os;
  for (size_t i = 0; i < cases.size() && i < rows.size(); ++i)
    if (rows[i]->timed_out())
      os << "timeout    " << cases[i].folder << " stopped at the per-case limit of "
         << limit_text(rows[i]->time_limit_s) << " (--case-timeout; jobs.txt line " << i + 1
         << ")\n";
  return os.str().empty() ? "" : os.str() + "\n";
}

bool any_case_failed(const std::vector<const RunFigures*>& rows) {
  for (const RunFigures* r : rows)
    if (r->crashed() || r->timed_out()) return true;
  return false;
}

int threads_per_case(int jobs) {
  const int cores = std::max(1u, std::thread::hardware_concurrency());
  return std::max(1, cores / std::max(1, jobs));
}

std::string timing_note(int jobs) {
  const int cores = std::max(1u, std::thread::hardware_concurrency());
  if (jobs > 1)
    return "Times: the cases ran " + std::to_string(jobs) + " at a time on " +
           std::to_string(cores) + " cores for their results; their times come from a separate "
           "pass that ran each case again alone, with " + std::to_string(threads_per_case(1)) +
           " thread(s) for BLAS and OpenMP and without charts or fields, so they are taken as "
           "--jobs 1 takes them.";
  std::string note = "Times: each case ran as its own process, " + std::to_string(jobs) +
                     " at a time on " + std::to_string(cores) + " cores, ";
  if (std::getenv("OPENBLAS_NUM_THREADS") || std::getenv("OMP_NUM_THREADS"))
    return note + "with the thread counts set in the environment (OPENBLAS_NUM_THREADS, "
                  "OMP_NUM_THREADS); cases running side by side share the machine.";
  return note + "each with " + std::to_string(threads_per_case(jobs)) +
         " thread(s) for BLAS and OpenMP (cores / jobs), so no case's factorisation competes "
         "for another's cores; memory bandwidth is still shared.";
}

std::string merged_timing_note() {
  return "Times: each case ran as its own `contact2d run` process from the job list "
         "(jobs.txt), on whatever machine and beside however many other cases the scheduler "
         "chose; its times are those its summary.json reports (process wall time and memory "
         "are not known to a merge).";
}

void run_cases(const std::vector<StudyCase>& cases, const std::string& study_dir, int jobs,
               double case_timeout_s,
               const std::function<void(size_t, const CaseOutcome&)>& on_done) {
  const std::string exe = this_executable();
  const std::vector<std::string> env = case_environment(
      std::max(1, std::min<int>(jobs, static_cast<int>(cases.size()))));
  std::atomic<size_t> next{0};
  std::mutex done_mutex;
  std::exception_ptr first_error;  // a worker's exception stops the pool, then is rethrown
  auto worker = [&] {
    try {
      for (size_t i = next++; i < cases.size(); i = next++) {
        const CaseOutcome outcome = run_one(exe, cases[i], study_dir, env, case_timeout_s);
        std::lock_guard<std::mutex> lock(done_mutex);
        if (first_error) return;
        on_done(i, outcome);
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(done_mutex);
      if (!first_error) first_error = std::current_exception();
      next = cases.size();
    }
  };
  const int threads = std::max(1, std::min<int>(jobs, static_cast<int>(cases.size())));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (first_error) std::rethrow_exception(first_error);
}

void retime_cases(const std::vector<StudyCase>& cases, const std::string& study_dir, int jobs,
                  double case_timeout_s, const std::vector<size_t>& skip, bool quiet,
                  const std::function<void(size_t, const RunFigures&)>& take) {
  if (jobs <= 1 || cases.empty()) return;
  std::vector<StudyCase> timing;
  std::vector<size_t> case_of;  // timing[k] times cases[case_of[k]]
  for (size_t i = 0; i < cases.size(); ++i) {
    if (std::find(skip.begin(), skip.end(), i) != skip.end()) continue;
    StudyCase c = cases[i];
    c.folder = "timing/" + c.folder;
    c.args.insert(c.args.end(),
                  {"--set", "output.charts=false", "--set", "output.fields=false"});
    timing.push_back(c);
    case_of.push_back(i);
  }
  if (timing.empty()) return;
  if (!quiet) std::cout << "timing     each case again, alone (times independent of --jobs)\n";
  size_t done = 0;
  run_cases(timing, study_dir, 1, case_timeout_s, [&](size_t k, const CaseOutcome& c) {
    RunFigures f;
    f.read(c);
    take(case_of[k], f);
    if (!quiet)
      std::cout << "[" << ++done << "/" << timing.size() << "] timed " << cases[case_of[k]].folder
                << (f.timed_out() ? ": timed out at " + limit_text(case_timeout_s) +
                                        "; the first run's times are kept"
                                  : ", solve " + csv_number(f.t_solve, 3) + " s")
                << std::endl;
  });
  fs::remove_all(study_dir + "/timing");
}

void take_times(RunFigures& row, const RunFigures& timed) {
  if (!timed.has_summary) return;
  row.t_mesh = timed.t_mesh;
  row.t_assemble = timed.t_assemble;
  row.t_solve = timed.t_solve;
  row.t_total = timed.t_total;
  row.wall = timed.wall;
}

double json_number(const nlohmann::json& j, std::initializer_list<const char*> path) {
  const nlohmann::json* node = &j;
  for (const char* key : path) {
    if (!node->is_object() || !node->contains(key)) return std::nan("");
    node = &(*node)[key];
  }
  return node->is_number() ? node->get<double>() : std::nan("");
}

std::string csv_number(double v, int digits) {
  if (!std::isfinite(v)) return "";
  std::ostringstream os;
  os << std::setprecision(digits) << v;
  return os.str();
}

std::string RunFigures::csv_status() const {
  std::string s = status;
  std::replace(s.begin(), s.end(), ',', ';');
  std::replace(s.begin(), s.end(), '"', '\'');
  std::replace(s.begin(), s.end(), '\n', ' ');
  return '"' + s + '"';
}

std::string no_summary_status(int exit_code) {
  // The run's documented exit codes (contact2d help): 2 bad input and 3 write failure end before
  // a summary.json exists; anything else without one (a signal, 128 + N) is a crash.
  const std::string why = " (exit " + std::to_string(exit_code) + ", no summary.json)";
  if (exit_code == 2) return "bad_input" + why;
  if (exit_code == 3) return "write_failed" + why;
  return "crashed" + why;
}

bool RunFigures::read(const CaseOutcome& c) {
  done = true;
  exit_code = c.exit_code;
  wall = c.wall_seconds;
  peak_rss_mb = c.peak_rss_mb;
  if (c.has_summary && c.summary.contains("process")) {
    // A merged case (run elsewhere): the run's own account of its wall time and memory.
    if (!std::isfinite(wall)) wall = json_number(c.summary, {"process", "wall_s"});
    if (!std::isfinite(peak_rss_mb)) peak_rss_mb = json_number(c.summary, {"process", "peak_rss_mb"});
  }
  if (c.timed_out) {  // whatever the stopped run left (an "interrupted" summary or nothing)
    status = "timeout";
    time_limit_s = c.time_limit_s;
    return false;
  }
  if (!c.malformed.empty()) {
    status = "malformed summary.json: " + c.malformed;
    return false;
  }
  if (!c.has_summary) {
    status = no_summary_status(c.exit_code);
    return false;
  }
  has_summary = true;
  const auto& s = c.summary;
  const auto found = s.find("status");
  status = found != s.end() && found->is_string() ? found->get<std::string>() : "unknown";
  time_limit_s = json_number(s, {"time_limit_s"});  // a case the study stopped (mark_timed_out)
  dofs = json_number(s, {"mesh", "dofs"});
  iterations = json_number(s, {"contact", "iterations"});
  newton = json_number(s, {"newton_iterations"});
  t_mesh = json_number(s, {"time_s", "mesh"});
  t_assemble = json_number(s, {"time_s", "assemble"});
  t_solve = json_number(s, {"time_s", "solve"});
  t_total = json_number(s, {"time_s", "total"});
  pivot = json_number(s, {"contact", "pivot_ratio"});
  penalty = json_number(s, {"contact", "penalty_max"});
  stiffness_max = json_number(s, {"contact", "stiffness_max"});
  zz = json_number(s, {"error", "relative_error"});
  if (converged()) {  // a failed run's contact figures are zeros, not results
    p_max = json_number(s, {"contact", "p_max"});
    length = json_number(s, {"contact", "length"});
    force = json_number(s, {"contact", "total_force"});
    penetration = json_number(s, {"contact", "max_penetration"});
    err_p0 = json_number(s, {"reference", "relative_error", "p_max"});
    err_b = json_number(s, {"reference", "relative_error", "contact_length"});
    stick_length = json_number(s, {"contact", "friction", "stick_length"});
    tangent_force = json_number(s, {"contact", "friction", "tangential_force"});
    err_stick = json_number(s, {"reference", "relative_error", "stick_length"});
    err_shear = json_number(s, {"reference", "relative_error", "shear_profile_l2"});
  }
  return true;
}

std::string study_out(const StudyOptions& o, const std::string& verb) {
  const std::string out =
      o.out.empty() ? "out/" + verb + "_" + fs::path(o.scene).stem().string() : o.out;
  create_output_folder(out);
  return out;
}

std::string percent_text(double v, int digits) {
  if (!std::isfinite(v)) return "–";
  std::ostringstream os;
  os << std::setprecision(digits) << 100.0 * v << " %";
  return os.str();
}

std::string seconds_text(double v) {
  std::ostringstream os;
  os << std::setprecision(3) << v << " s";
  return os.str();
}

}  // namespace c2d::app
