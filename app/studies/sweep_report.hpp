// sweep's rows and report: what a sweep's cases gave (SweepRow, SweepStudy), sweep.csv,
// sweep.md (verdict first), sweep.html and the chart. Internal to studies/ (sweep.cpp): the same
// report ends a sweep that ran its cases and a merge of one whose cases ran elsewhere.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "app/studies/study.hpp"
#include "app/studies/study_metric.hpp"

namespace c2d::app {

/// One case of a sweep: its figures, the swept value and its reading of the metric.
struct SweepRow : RunFigures {
  double value = 0.0;
  double metric = std::nan("");  ///< the run's reading of the study's metric
};

/// What the steps of a sweep share: the scene (as given, for titles), the swept key, the
/// metric and accuracy it is judged by, how its times were taken, the cases and their rows
/// (same order), and the baseline: the exact method on the same mesh, the last case when the
/// swept key is a regularisation's parameter.
struct SweepStudy {
  std::string scene, key, out, timing;
  std::string units;  ///< the scene's `units` (the penetration panel's label)
  StudyMetric metric;
  double accuracy = 0.01;
  double case_timeout_s = 0;  ///< the per-case limit (for the job list; 0: none)
  SlurmSettings slurm;        ///< slurm.sh's #SBATCH lines (for the job list)
  std::vector<StudyCase> cases;
  std::vector<SweepRow> rows;
  std::string baseline_method;  ///< "" without a baseline
  SweepRow baseline;

  /// The row of case i (the baseline's after the swept values').
  SweepRow& row(size_t i) { return i < rows.size() ? rows[i] : baseline; }
};

/// The exact method a regularised sweep is held against.
inline constexpr const char* kBaselineMethod = "lagrange";

/// sweep.csv: the header and a line per finished row (the baseline is in the verdict).
std::string sweep_csv(const SweepStudy& s);

/// A finished case's row, with its reading of the study's metric.
void read_sweep_row(const SweepStudy& s, SweepRow& r, const CaseOutcome& c);

/// sweep.csv, sweep.md, sweep.html and the chart from the finished rows, listing the `missing`
/// cases and those that timed out; the verdict on the terminal unless quiet. Returns 1 when a
/// case crashed, timed out or is missing or the chart failed, else 0.
int report_sweep(const SweepStudy& s, const std::vector<size_t>& missing, bool quiet);

}  // namespace c2d::app
