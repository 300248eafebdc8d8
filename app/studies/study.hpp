// What the studies over many runs of one scene share (compare, sweep, bench; calibrate takes
// their options). Each case is a separate `contact2d run` process
// (up to --jobs at a time): cases cannot disturb one another (gmsh keeps global state; a crash
// in one case is that case's status), every case writes its own folder, and the table is
// rewritten after each finished case, so an interrupted study keeps its finished rows.
#pragma once

#include <cmath>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace c2d::app {

/// One `contact2d run` of a study.
struct StudyCase {
  std::vector<std::string> args;  ///< after "run": scene, --method, --set ..., --out, --quiet
  std::string out_dir;
};

struct CaseOutcome {
  int exit_code = -1;
  bool has_summary = false;
  nlohmann::json summary;  ///< the case's summary.json (null when none was written)
  double wall_seconds = 0.0;
  double peak_rss_mb = 0.0;  ///< the process's peak resident memory (wait4's ru_maxrss)
};

/// The threads each case of a study gets for BLAS and OpenMP: the machine's cores shared among
/// the `jobs` cases that run at once, at least 1. OpenBLAS threads of two factorisations on the
/// same cores slowed a 26k-DOF factorisation 20x and flipped compare's ranking with --jobs 2.
int threads_per_case(int jobs);
/// One sentence for a study's report: how its times were taken.
std::string timing_note(int jobs);

/// Runs the cases with at most `jobs` concurrent processes of this executable (each with
/// threads_per_case(jobs) threads unless the environment sets them); `on_done` is
/// called once per case as it finishes, never concurrently.
void run_cases(const std::vector<StudyCase>& cases, int jobs,
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
  bool converged() const { return status == "converged"; }

  /// Fills the figures from a finished case; false when it left no summary (a crash).
  bool read(const CaseOutcome& c);
  /// The status as one quoted CSV cell (commas, quotes and line breaks replaced).
  std::string csv_status() const;
};

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
};

/// The study's output folder, created: --out, else out/<verb>_<scene file stem>.
std::string study_out(const StudyOptions& o, const std::string& verb);

/// "12.3 %" with `digits` significant digits; "–" when not finite.
std::string percent_text(double v, int digits = 3);

/// "1.23 s".
std::string seconds_text(double v);

}  // namespace c2d::app
