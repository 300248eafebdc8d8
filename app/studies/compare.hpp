// `contact2d compare`: every contact method on the same scene over refinement levels, each case
// a separate `contact2d run` (see study.hpp); a table, a verdict and charts.
#pragma once

#include <string>
#include <vector>

#include "app/studies/study.hpp"

namespace c2d::app {

struct CompareOptions : StudyOptions {
  std::vector<std::string> methods;  ///< empty: all six
  int levels = 1;
};

/// `contact2d compare`: writes compare.csv, compare.md (verdict first), accuracy_time,
/// pressure_profiles and penetration charts. Returns the exit code (0 when every case ran,
/// converged or not; 1 when a case crashed or a chart failed).
int run_compare(const CompareOptions& o);

}  // namespace c2d::app
