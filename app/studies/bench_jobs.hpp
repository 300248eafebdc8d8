// Whether a study's times depend on how many cases run side by side (issue 19, item 4): the
// bench runs one compare with --jobs 1 and with --jobs 2 and sets their solve times side by
// side. Internal to studies/ (bench.cpp).
#pragma once

#include <string>
#include <vector>

namespace c2d::app {

/// One compare, run `repeats` times per jobs setting (interleaved): per method the fastest
/// solve time of each setting (the machine's noise, ±25 % between repeats on a shared 2-core
/// VM, is the repeats' spread, not a property of the study).
struct JobsComparison {
  std::string scene = "hertz_rigid.toml", methods = "lagrange,ssn,penalty,auglag";
  int repeats = 0;
  std::vector<std::string> method_names;
  std::vector<double> solve_jobs1, solve_jobs2;  ///< fastest over the repeats
  std::vector<double> spread;                    ///< largest over smallest, over every repeat
  std::string error;                             ///< why it could not be measured; "" if it was
  /// The largest |t₂ − t₁| / t₁ over the methods (NaN when not measured).
  double worst_difference() const;
};

/// Runs `contact2d compare hertz_rigid.toml --methods ... --levels 1 --jobs J` for J = 1, 2
/// into out/jobs_J_R (R = repeat), each as its own process whose cases have the bench's
/// per-case limit `case_timeout_s` (0: none); not for `quick`.
JobsComparison compare_jobs(const std::string& examples, const std::string& out, bool quick,
                            double case_timeout_s);

/// The table: method, fastest solve with --jobs 1 and --jobs 2, their difference, the spread.
std::string jobs_md(const JobsComparison& c);

}  // namespace c2d::app
