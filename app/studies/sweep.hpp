// `contact2d sweep`: one scene key over a range of values, each case a separate `contact2d run`
// (see study.hpp); a table, the range that meets an accuracy, and charts.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "app/studies/study.hpp"

namespace c2d::app {

struct StudyManifest;

/// sets: exactly one of them a range, key=a:b:log:n, key=a:b:lin:n or key=v1,v2,...
struct SweepOptions : StudyOptions {
  double accuracy = 0.01;  ///< relative p_max error a value must meet
};

/// The values of a range spec (a:b:log:n, a:b:lin:n or a comma list); throws InputError naming
/// `where` on a malformed spec.
std::vector<double> parse_range(const std::string& spec, const std::string& where);

/// The x range the sweep chart's panels share: every value swept (converged or not) and the
/// seed rule's k (NaN: none) inside it with a margin (on a log axis out to the next whole
/// decades, a tenth of one at least; on a linear one 5 % of the span), so that the markers of
/// failed values and of the seed rule are drawn within the axes, not beside them.
std::pair<double, double> sweep_x_range(std::vector<double> values, double seed_k, bool log_x);

/// `contact2d sweep`: writes the study's job list and manifest (job_list.hpp), then, unless
/// o.job_list, runs the cases and writes sweep.csv, sweep.md and sweep.png/svg (p_max error,
/// penetration, iterations, solve time and the factorisation's pivot ratio against the swept
/// value, failed values marked). Returns the exit code.
int run_sweep(const SweepOptions& o);

/// `contact2d merge` of a sweep: the same report from the case folders that have finished,
/// listing the others. Returns 1 when a case is missing (or the chart failed), else 0.
int merge_sweep(const StudyManifest& m, bool quiet);

}  // namespace c2d::app
