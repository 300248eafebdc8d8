#include "app/studies/study.hpp"
#include "app/output_folder.hpp"

#include <algorithm>
#include <cstdlib>
#include <atomic>
#include <chrono>
#include <exception>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <mutex>
#include <sstream>
#include <thread>

#include "app/process.hpp"

namespace fs = std::filesystem;

namespace c2d::app {

namespace {

CaseOutcome run_one(const std::string& exe, const StudyCase& c,
                    const std::vector<std::string>& env) {
  CaseOutcome out;
  fs::create_directories(c.out_dir);
  std::vector<std::string> args{"run"};
  args.insert(args.end(), c.args.begin(), c.args.end());
  const auto t0 = std::chrono::steady_clock::now();
  const ProcessOutcome run = run_process(exe, args, c.out_dir + "/stdout.log", env);
  if (run.started) out.exit_code = run.exit_code, out.peak_rss_mb = run.peak_rss_mb;
  out.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::ifstream in(c.out_dir + "/summary.json");
  if (in) {
    try {
      out.summary = nlohmann::json::parse(in);
      out.has_summary = true;
    } catch (const std::exception&) {
      out.has_summary = false;
    }
  }
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

}  // namespace

int threads_per_case(int jobs) {
  const int cores = std::max(1u, std::thread::hardware_concurrency());
  return std::max(1, cores / std::max(1, jobs));
}

std::string timing_note(int jobs) {
  const int cores = std::max(1u, std::thread::hardware_concurrency());
  std::string note = "Times: each case ran as its own process, " + std::to_string(jobs) +
                     " at a time on " + std::to_string(cores) + " cores, ";
  if (std::getenv("OPENBLAS_NUM_THREADS") || std::getenv("OMP_NUM_THREADS"))
    return note + "with the thread counts set in the environment (OPENBLAS_NUM_THREADS, "
                  "OMP_NUM_THREADS); cases running side by side share the machine.";
  return note + "each with " + std::to_string(threads_per_case(jobs)) +
         " thread(s) for BLAS and OpenMP (cores / jobs), so no case's factorisation competes "
         "for another's cores; memory bandwidth is still shared.";
}

void run_cases(const std::vector<StudyCase>& cases, int jobs,
               const std::function<void(size_t, const CaseOutcome&)>& on_done) {
  const std::string exe = fs::read_symlink("/proc/self/exe").string();
  const std::vector<std::string> env = case_environment(
      std::max(1, std::min<int>(jobs, static_cast<int>(cases.size()))));
  std::atomic<size_t> next{0};
  std::mutex done_mutex;
  std::exception_ptr first_error;  // a worker's exception stops the pool, then is rethrown
  auto worker = [&] {
    try {
      for (size_t i = next++; i < cases.size(); i = next++) {
        const CaseOutcome outcome = run_one(exe, cases[i], env);
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

bool RunFigures::read(const CaseOutcome& c) {
  done = true;
  exit_code = c.exit_code;
  wall = c.wall_seconds;
  peak_rss_mb = c.peak_rss_mb;
  if (!c.has_summary) {
    status = "crashed (exit " + std::to_string(c.exit_code) + ", no summary.json)";
    return false;
  }
  const auto& s = c.summary;
  status = s.value("status", std::string("unknown"));
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
