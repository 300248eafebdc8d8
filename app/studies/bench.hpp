// `contact2d bench`: a fixed ladder of scenes at growing size, each a separate `contact2d run`
// process, timed per phase, with its peak memory and its accuracy against the scene's reference;
// a methods panel (every contact method on the time-to-accuracy Hertz scenes); an in-process
// measurement of assembly throughput. Writes bench.csv, bench.md (the targets beside the
// measured figures) and charts (time against DOFs with fitted slopes, accuracy against time).
// Figures, not assertions: nothing here fails on a slow machine.
#pragma once

#include <string>
#include <vector>

#include "app/studies/study.hpp"

namespace c2d::app {

struct BenchOptions {
  bool quick = false;    ///< the small ladder (under a minute): CI smoke use
  std::string out;       ///< default out/bench
  std::string examples;  ///< folder of the bundled scenes (default: the source tree's)
  bool quiet = false;
  bool job_list = false;  ///< write the ladder as a job list (job_list.hpp) instead of running it
  double case_timeout_s = kDefaultCaseTimeout;  ///< per run; 0: none
  SlurmSettings slurm;                          ///< slurm.sh's #SBATCH lines
};

/// One `contact2d run` of the ladder.
struct BenchCase {
  std::string family;   ///< elasticity, hertz_rigid, hertz_block, two_cantilevers, methods,
                        ///< time_to_accuracy
  std::string scene;    ///< file name in the examples folder
  std::string element;  ///< T3 or T6
  std::string method;   ///< contact method ("" = the scene's / none)
  double mesh_scale = 1.0;
  std::string nominal;            ///< the rung's nominal size ("10k", "100k", "1M") or a label
  std::vector<std::string> sets;  ///< further --set overrides
};

/// The ladder: the quick one for CI, else the full one (about 10k, 100k and 1M DOFs).
std::vector<BenchCase> bench_ladder(bool quick);

/// bench.csv's header (the columns tests check).
extern const char* const kBenchCsvHeader;

/// Writes the ladder's job list and manifest (job_list.hpp), then, unless o.job_list, runs it;
/// returns 0 when every case ran and the files were written (a case that did not converge is a
/// row with its status, not a failure of the benchmark), 1 otherwise (a case crashed or was
/// stopped at o.case_timeout_s, or a chart failed).
int run_bench(const BenchOptions& o);

struct StudyManifest;

/// `contact2d merge` of a bench: the same report from the case folders that have finished,
/// listing the others (process wall time and peak memory are unknown to a merge). Returns 1
/// when a case is missing (or a chart failed), else 0.
int merge_bench(const StudyManifest& m, bool quiet);

/// Least-squares slope of log(y) against log(x) over the points with x, y > 0 (NaN for fewer
/// than two): the empirical order of a cost in the problem size.
double loglog_slope(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace c2d::app
