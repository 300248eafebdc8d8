// compare's report: the rows read from the case folders, compare.csv, compare.md (verdict,
// observed orders, table, missing cases), orders.csv and the charts. Internal to studies/
// (compare.cpp): the same report ends a comparison that ran its cases and a merge of one whose
// cases ran elsewhere.
#pragma once

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "app/report/hertz.hpp"
#include "app/report/html_report.hpp"
#include "app/studies/study.hpp"
#include "app/studies/study_metric.hpp"

namespace c2d::app {

struct CompareRow : RunFigures {
  int level = 0;
  std::string method;
  double mesh_scale = 1.0;
  double err_profile = std::nan("");
  double fit_p0 = std::nan(""), fit_b = std::nan(""), err_fit_p0 = std::nan(""),
         err_fit_b = std::nan("");  ///< Hertz form fitted to the nodal pressures (Ceres)
  std::vector<std::pair<double, double>> profile;
  double metric = std::nan("");  ///< the run's reading of the study's metric (study_metric.hpp)
};

/// What the steps of a comparison share: the scene (as given, for titles), the chosen methods
/// and levels, the metric it is judged by, how its times were taken, the cases
/// and their rows (one per method and level, in the same order).
struct CompareStudy {
  std::string scene;
  std::vector<std::string> methods;
  int levels = 1;
  std::optional<HertzReference> hertz;
  StudyMetric metric;  ///< empty: the scene has no reference and none was asked for
  std::string units;   ///< the scene's `units` (axis labels)
  std::string out;
  std::string timing;  ///< timing_note() or merged_timing_note()
  double case_timeout_s = 0;  ///< the per-case limit (for the job list; 0: none)
  SlurmSettings slurm;        ///< slurm.sh's #SBATCH lines (for the job list)
  std::vector<StudyCase> cases;
  std::vector<CompareRow> rows;
};

/// The accuracy a row reached on the study's metric (NaN when it has none). Against a baseline
/// run (a metric without reference: the exact method's run on the finest level it converged),
/// the rows of the baseline's level have none: there the difference is between methods on one
/// mesh, not a discretisation error.
double accuracy(const CompareStudy& s, const CompareRow& r);

/// The metric's label, with the baseline run it is measured against, if any.
std::string metric_name(const CompareStudy& s);

/// compare's charts (compare_charts.cpp): accuracy against time, the finest level's pressure
/// profiles with Hertz's, the penetration per level; each drawn only while the ones before it
/// succeeded, the others listed in `charts` as not drawn. Returns "" or the first failure.
std::string draw_compare_charts(const CompareStudy& s, std::vector<ReportChart>& charts);

/// compare.csv: the header and a line per finished row.
std::string compare_csv(const std::vector<CompareRow>& rows);

/// A finished case's row: its figures, and for a converged run its pressure profile, with the
/// Hertz form fitted to it. False when the case left no summary (a crash).
bool read_row(CompareRow& r, const CaseOutcome& c, const std::string& dir,
              const CompareStudy& s);

/// Writes compare.csv, compare.md, orders.csv and the charts from the finished rows, listing
/// the `missing` and the timed-out cases; prints the verdict unless quiet. Returns the exit
/// code: 1 when a case crashed, timed out or is missing or a chart failed, else 0.
int report_compare(const CompareStudy& s, const std::vector<size_t>& missing, bool quiet);

}  // namespace c2d::app
