// The command line of contact2d: every verb's options, parsed once.
#pragma once

#include <string>
#include <vector>

#include "app/studies/slurm_settings.hpp"

namespace c2d::app {

/// Exit codes (DESIGN §5): ok, a solve failed (results so far kept), bad input, the output
/// could not be written (a full disk: the system's reason and the output folder named).
constexpr int kExitOk = 0, kExitSolveFailed = 1, kExitBadInput = 2, kExitWriteFailed = 3;

/// Everything a verb may take; `scene` is the positional argument (a scene file, or the output
/// folder for trace and plot).
struct Options {
  std::string verb, scene;
  std::vector<std::string> sets;
  std::string out, method, methods, data;
  std::string metric;  // compare, sweep: what to judge the runs by (study_metric.hpp)
  std::vector<std::string> fits;
  int levels = 1, jobs = 1;
  double accuracy = 0.01;
  bool quiet = false, help = false;
  // plot
  std::vector<std::string> fields;
  std::string zoom, deformed;
  int step = 0, cycle = -1, plot_levels = 12;
  bool edges = false;
  // run --adapt: overrides of the [adapt] table
  bool adapt = false;
  std::vector<std::string> adapt_sets;
  // compare, sweep, bench: write the cases as a job list instead of running them
  bool job_list = false;
  // compare, sweep, bench: each case's time limit in seconds (0: none; negative: the studies'
  // default, kDefaultCaseTimeout)
  double case_timeout = -1;
  // compare, sweep, bench: what slurm.sh asks of the cluster per task
  SlurmSettings slurm;
  // bench
  bool quick = false;
  std::string examples;
};

/// The non-empty items of a comma-separated list ("a,b,,c" -> a, b, c).
std::vector<std::string> split_list(const std::string& text);

/// Parses argv (verb first). Throws InputError naming the option for an unknown option, a
/// missing or malformed value, or a second positional argument.
Options parse_args(int argc, char** argv);

}  // namespace c2d::app
