// `contact2d compare`: every contact method on the same scene over refinement levels, each case
// a separate `contact2d run` (see study.hpp); a table, a verdict and charts.
#pragma once

#include <string>
#include <vector>

#include "app/studies/study.hpp"

namespace c2d::app {

struct StudyManifest;

struct CompareOptions : StudyOptions {
  std::vector<std::string> methods;  ///< empty: all six
  int levels = 1;
};

/// `contact2d compare`: writes the study's job list and manifest (job_list.hpp), then, unless
/// o.job_list, runs the cases and writes compare.csv, compare.md (verdict first), orders.csv and
/// the accuracy_time, pressure_profiles and penetration charts. Returns the exit code (0 when
/// every case ran, converged or not, or the job list was written; 1 when a case crashed, timed
/// out (o.case_timeout_s) or a chart failed).
int run_compare(const CompareOptions& o);

/// `contact2d merge` of a compare study: the same report from the case folders that have
/// finished, listing the others. Returns 1 when a case is missing (or a chart failed), else 0.
int merge_compare(const StudyManifest& m, bool quiet);

}  // namespace c2d::app
