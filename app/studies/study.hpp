// What the studies over many runs of one scene share (compare, sweep, bench; calibrate takes
// their options). Each case is a separate `contact2d run` process
// (up to --jobs at a time): cases cannot disturb one another (gmsh keeps global state; a crash
// in one case is that case's status), every case writes its own folder, and the table is
// rewritten after each finished case, so an interrupted study keeps its finished rows.
// A study is three steps that every path shares: plan the cases (and write them as a job list,
// job_list.hpp), run them (here, or with --job-list by any scheduler), and report from the
// case folders that hold a summary.json (at the end of a run, or by `contact2d merge`).
// A case runs for at most --case-timeout seconds: one that never ends is stopped with its row
// `timeout`, and the study goes on with the others.
#pragma once

#include <cmath>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/studies/slurm_settings.hpp"

namespace c2d::app {

/// One `contact2d run` of a study.
struct StudyCase {
  std::vector<std::string> args;  ///< after "run": the scene, --method, --set ... (no --out)
  std::string folder;             ///< the case's folder, relative to the study's
};

/// The arguments of a case's `contact2d run` into `out_dir`: "run", the case's, --out, --quiet.
std::vector<std::string> run_arguments(const StudyCase& c, const std::string& out_dir);

/// This program's absolute path (what the cases run).
std::string this_executable();

/// The default per-case time limit (--case-timeout), in seconds: 30 minutes, 90 times the
/// bench's longest case (a 1.2M-DOF Hertz run, 17 to 20 s scene to summary on 2 cores), so that
/// a slow machine or a larger scene is not cut short, and a case that never ends still ends.
constexpr double kDefaultCaseTimeout = 1800;
/// After SIGTERM, how long a case's process group has before SIGKILL (a `contact2d run` needs
/// milliseconds to write its "interrupted" summary and end).
constexpr double kCaseKillGrace = 5;

struct CaseOutcome {
  int exit_code = -1;
  bool timed_out = false;              ///< stopped at the study's time limit (this program ran it)
  double time_limit_s = std::nan("");  ///< that limit
  bool has_summary = false;
  nlohmann::json summary;  ///< the case's summary.json (null when none was written)
  std::string malformed;   ///< why its summary.json could not be read ("" when read or absent)
  double wall_seconds = std::nan("");  ///< known only when this program ran the case
  double peak_rss_mb = std::nan("");   ///< the process's peak resident memory (wait4's ru_maxrss)
};

/// What a case left in its folder: its summary.json, if any, and the exit code `contact2d run`
/// gives with that summary (0 converged, 1 not; -1 without one). A summary.json that is there but
/// cannot be read as one (not a regular file, over 64 MiB, nested deeper than 64 levels, not
/// JSON, or a value the studies read of the wrong type) is no summary, and `malformed` says why.
/// Process figures (wall time, memory) stay NaN.
CaseOutcome read_case_folder(const std::string& dir);

/// Reads the cases of the study in `study_dir` that have finished (their folder holds a
/// summary.json, readable or malformed), calling `on_read` for each in order; returns the indices
/// of the others.
std::vector<size_t> read_finished_cases(
    const std::vector<StudyCase>& cases, const std::string& study_dir,
    const std::function<void(size_t, const CaseOutcome&)>& on_read);

/// The missing cases for a study's markdown report ("" when none): a section listing each
/// case's folder and its line in jobs.txt.
std::string missing_cases_md(const std::vector<StudyCase>& cases,
                             const std::vector<size_t>& missing);
/// The same for the terminal ("" when none): a line per missing case, then how to run them
/// again (their jobs.txt lines through parallel, or an sbatch --array of them).
std::string missing_cases_text(const std::vector<StudyCase>& cases,
                               const std::vector<size_t>& missing);

/// The threads each case of a study gets for BLAS and OpenMP: the machine's cores shared among
/// the `jobs` cases that run at once, at least 1. OpenBLAS threads of two factorisations on the
/// same cores slowed a 26k-DOF factorisation 20x and flipped compare's ranking with --jobs 2.
int threads_per_case(int jobs);
/// One sentence for a study's report: how its times were taken.
std::string timing_note(int jobs);

/// The same sentence for a report merged from case folders (`contact2d merge`).
std::string merged_timing_note();

/// Runs the cases into their folders under `study_dir` with at most `jobs` concurrent processes
/// of this executable (each with threads_per_case(jobs) threads unless the environment sets
/// them); `on_done` is called once per case as it finishes, never concurrently. A case still
/// running after `case_timeout_s` seconds (0: no limit) is stopped (ProcessLimit: SIGTERM to
/// its process group, SIGKILL kCaseKillGrace later) and its outcome says timed_out; the
/// "interrupted" summary.json such a run leaves gets status "timeout" and the limit
/// (time_limit_s), so that a later merge reports it as the study did.
void run_cases(const std::vector<StudyCase>& cases, const std::string& study_dir, int jobs,
               double case_timeout_s,
               const std::function<void(size_t, const CaseOutcome&)>& on_done);

/// What every study reads from a case's summary.json.
struct RunFigures {
  bool done = false;
  int exit_code = -1;
  std::string status = "not run";
  double dofs = std::nan(""), iterations = std::nan(""), newton = std::nan("");
  double t_mesh = std::nan(""), t_assemble = std::nan(""), t_solve = std::nan(""),
         t_total = std::nan(""), wall = std::nan("");
  double p_max = std::nan(""), length = std::nan(""), force = std::nan(""),
         penetration = std::nan("");
  double err_p0 = std::nan(""), err_b = std::nan(""), zz = std::nan("");
  double pivot = std::nan(""), penalty = std::nan(""), stiffness_max = std::nan("");
  /// Friction (NaN without): the stick zone's length, the total tangential force, and their
  /// errors against a Cattaneo–Mindlin reference (the stick length's and the shear profile's).
  double stick_length = std::nan(""), tangent_force = std::nan("");
  double err_stick = std::nan(""), err_shear = std::nan("");

  double peak_rss_mb = std::nan("");
  bool has_summary = false;
  double time_limit_s = std::nan("");  ///< the limit a timed-out case was stopped at
  bool converged() const { return status == "converged"; }
  /// Stopped at the study's per-case time limit.
  bool timed_out() const { return done && status == "timeout"; }
  /// Ran, but left no summary.json (refused its input, could not write, or died; not at the
  /// time limit): the status says which (no_summary_status).
  bool crashed() const { return done && !has_summary && !timed_out(); }

  /// Fills the figures from a finished case; false when it left no summary (a crash) or a
  /// malformed one (the status says "malformed summary.json: " and why).
  bool read(const CaseOutcome& c);
  /// The status as one quoted CSV cell (commas, quotes and line breaks replaced).
  std::string csv_status() const;
};

/// The times of cases that ran `jobs` > 1 at a time, taken again in a separate pass: each case
/// runs once more alone, with every core's threads and without charts or fields, into
/// study_dir/timing/ (removed after), and `take(i, figures)` receives that run's figures. Cases
/// side by side measure each other (on 2 cores compare's solve times differed by up to 29 %
/// between --jobs 1 and 2); alone, every case is timed as --jobs 1 times it. No-op for jobs 1.
/// Each timing run has the same limit, `case_timeout_s`; the cases in `skip` (those that timed
/// out the first time, which would only take the limit again) are not run.
void retime_cases(const std::vector<StudyCase>& cases, const std::string& study_dir, int jobs,
                  double case_timeout_s, const std::vector<size_t>& skip, bool quiet,
                  const std::function<void(size_t, const RunFigures&)>& take);
/// Replaces the times of `row` (mesh, assemble, solve, total, process wall) by those of a timing
/// run, when that run left a summary.
void take_times(RunFigures& row, const RunFigures& timed);

/// The indices of the rows that timed out.
template <class Row>
std::vector<size_t> timed_out_rows(const std::vector<Row>& rows) {
  std::vector<size_t> out;
  for (size_t i = 0; i < rows.size(); ++i)
    if (rows[i].timed_out()) out.push_back(i);
  return out;
}

/// The rows of a study as their figures, in the order of its cases.
template <class Row>
std::vector<const RunFigures*> figures_of(const std::vector<Row>& rows) {
  std::vector<const RunFigures*> out;
  for (const auto& r : rows) out.push_back(&r);
  return out;
}

/// The cases stopped at the per-case time limit, for a study's markdown report ("" when none):
/// a section saying what happened to them, with each case's folder, its limit and its line in
/// jobs.txt. `rows[i]` is the row of `cases[i]`.
std::string timed_out_cases_md(const std::vector<StudyCase>& cases,
                               const std::vector<const RunFigures*>& rows);
/// The same for the terminal ("" when none): a line per case.
std::string timed_out_cases_text(const std::vector<StudyCase>& cases,
                                 const std::vector<const RunFigures*>& rows);
/// Whether a case crashed or timed out: what makes a study's exit code 1 (a case that ran and
/// did not converge is a row with its status, not a failure of the study).
bool any_case_failed(const std::vector<const RunFigures*>& rows);

/// The status of a case that ended with `exit_code` and left no summary.json:
/// "bad_input (exit 2, no summary.json)", "write_failed (exit 3, ...)", else "crashed (exit N,
/// ...)" (a signal N - 128, or a code the run does not document).
std::string no_summary_status(int exit_code);

/// A number as a CSV cell with `digits` significant digits; empty when not finite.
std::string csv_number(double v, int digits = 8);

/// The number at `path` in `j`, NaN when absent or not a number.
double json_number(const nlohmann::json& j, std::initializer_list<const char*> path);

/// What every study verb takes: the scene, overrides, the contact method, output.
struct StudyOptions {
  std::string scene;
  std::string method;  ///< empty: the scene's
  std::vector<std::string> sets;
  int jobs = 1;
  std::string out;
  bool quiet = false;
  bool job_list = false;  ///< write the cases as a job list (job_list.hpp) instead of running them
  double case_timeout_s = kDefaultCaseTimeout;  ///< per case; 0: none
  std::string metric;  ///< compare, sweep: --metric (study_metric.hpp); empty: the default
  SlurmSettings slurm;                          ///< slurm.sh's #SBATCH lines
};

/// The study's output folder, created: --out, else out/<verb>_<scene file stem>.
std::string study_out(const StudyOptions& o, const std::string& verb);

/// "12.3 %" with `digits` significant digits; "–" when not finite.
std::string percent_text(double v, int digits = 3);

/// "1.23 s".
std::string seconds_text(double v);

}  // namespace c2d::app
