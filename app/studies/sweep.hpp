// `contact2d sweep`: one scene key over a range of values, each case a separate `contact2d run`
// (see study.hpp); a table, the range that meets an accuracy, and charts.
#pragma once

#include <string>
#include <vector>

#include "app/studies/study.hpp"

namespace c2d::app {

/// sets: exactly one of them a range, key=a:b:log:n, key=a:b:lin:n or key=v1,v2,...
struct SweepOptions : StudyOptions {
  double accuracy = 0.01;  ///< relative p_max error a value must meet
};

/// The values of a range spec (a:b:log:n, a:b:lin:n or a comma list); throws InputError naming
/// `where` on a malformed spec.
std::vector<double> parse_range(const std::string& spec, const std::string& where);

/// `contact2d sweep`: writes sweep.csv, sweep.md and sweep.png/svg (p_max error, penetration,
/// iterations, solve time and the factorisation's pivot ratio against the swept value, failed
/// values marked). Returns the exit code.
int run_sweep(const SweepOptions& o);

}  // namespace c2d::app
