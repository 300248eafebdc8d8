// The study verbs: compare, sweep, calibrate, bench and merge, each handing its options to
// studies/.
#include "app/cli/verbs.hpp"
#include "app/process.hpp"
#include "app/studies/bench.hpp"
#include "app/studies/calibrate.hpp"
#include "app/studies/compare.hpp"
#include "app/studies/merge.hpp"
#include "app/studies/sweep.hpp"
#include "core/errors.hpp"

namespace c2d::app {

namespace {

/// The options every study verb shares.
void fill_study(const Options& o, StudyOptions& s) {
  s.scene = o.scene;
  s.method = o.method;
  s.sets = o.sets;
  s.jobs = o.jobs;
  s.out = o.out;
  s.quiet = o.quiet;
  s.job_list = o.job_list;
  s.metric = o.metric;
  s.slurm = o.slurm;
}

/// For the verbs that run cases: their time limit, and SIGINT and SIGTERM passed on to them (a
/// case with a time limit leads its own process group, out of reach of the terminal's Ctrl-C).
void limit_cases(const Options& o, double& case_timeout_s) {
  if (o.case_timeout >= 0) case_timeout_s = o.case_timeout;
  forward_interrupts_to_limited_children();
}

}  // namespace

int cmd_compare(const Options& o) {
  CompareOptions c;
  fill_study(o, c);
  c.methods = split_list(o.methods);
  c.levels = o.levels;
  limit_cases(o, c.case_timeout_s);
  return run_compare(c);
}

int cmd_sweep(const Options& o) {
  SweepOptions w;
  fill_study(o, w);
  w.accuracy = o.accuracy;
  limit_cases(o, w.case_timeout_s);
  return run_sweep(w);
}

int cmd_calibrate(const Options& o) {
  CalibrateOptions c;
  fill_study(o, c);
  c.data = o.data;
  c.fits = o.fits;
  return run_calibrate(c);
}

int cmd_bench(const Options& o) {
  if (!o.scene.empty()) throw InputError(o.scene + ": unexpected argument (bench takes no scene)");
  BenchOptions b;
  b.quick = o.quick;
  b.out = o.out;
  b.examples = o.examples.empty() ? C2D_EXAMPLES_DIR : o.examples;
  b.quiet = o.quiet;
  b.job_list = o.job_list;
  b.slurm = o.slurm;
  limit_cases(o, b.case_timeout_s);
  return run_bench(b);
}

int cmd_merge(const Options& o) { return run_merge(o.scene, o.quiet); }

}  // namespace c2d::app
