// The bench's report: bench.md's tables and the charts, from the rows of the finished runs.
// Internal to studies/ (bench.cpp).
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "app/report/html_report.hpp"
#include "app/studies/bench.hpp"
#include "app/studies/bench_jobs.hpp"
#include "app/studies/study.hpp"

namespace c2d::app {

/// What a bench row holds: the case, the figures every study reads (RunFigures), and the
/// solver phases, detection and accuracy its summary.json gave.
struct BenchRow : RunFigures {
  BenchCase c;
  double factorizations = NAN;
  double t_symbolic = NAN, t_numeric = NAN, t_triangular = NAN, t_contact_other = NAN,
         t_detection = NAN, t_recovery = NAN, t_output = NAN;
  std::string accuracy_measure;
  double accuracy = NAN, overhead = NAN;
  double one_linear_solve = NAN;  ///< symbolic + one numeric factorisation of this run
  /// Load steps converged, and Newton iterations and factorisations per converged step.
  double steps = NAN, newton_per_step = NAN, factorizations_per_step = NAN;
  /// Whether the run is a load-stepped contact run (its own table and targets).
  bool stepped() const { return c.family == "stepped" || c.family == "two_cantilevers"; }
  double excluding_mesh() const { return t_total - t_mesh; }
};

/// In-process refill assembly throughput on structured grids, one thread and all threads.
struct Throughput {
  double t3_serial = NAN, t6_serial = NAN, t3_parallel = NAN, t6_parallel = NAN;
  int threads = 1;
};

/// A bench figure as a CSV or table cell: 6 significant digits, empty when not finite.
std::string bench_cell(double v);

/// Three significant digits.
std::string rounded(double v);

/// The targets with the measured figure beside each, and a verdict.
/// `jobs`: compare's solve times with --jobs 1 and 2 (not measured by a merge).
std::string targets_md(const std::vector<BenchRow>& rows, const Throughput& t, bool quick,
                       const JobsComparison& jobs);
/// The fitted slope of log time against log DOFs, per phase, for every ladder family and element.
std::string phase_slopes_md(const std::vector<BenchRow>& rows);

/// The ladder's runs: phase times, memory, accuracy, overhead.
std::string ladder_md(const std::vector<BenchRow>& rows);

/// Every method on the time-to-accuracy scenes.
std::string methods_md(const std::vector<BenchRow>& rows);

/// The load-stepped contact runs: steps, Newton iterations and factorisations per step.
std::string stepped_md(const std::vector<BenchRow>& rows);

/// Time against DOFs, log-log: left, the whole run without meshing per family; right, the
/// phases of the linear elastic T6 ladder. Each line's title carries its fitted slope. Adds the
/// chart (written or why not) to `charts`; returns "" or the chart's failure.
std::string chart_time(const std::string& out, const std::vector<BenchRow>& rows,
                       std::vector<ReportChart>& charts);

/// Accuracy against time: every method on the time-to-accuracy scenes (one panel per scene,
/// one line per method through its meshes), with the lagrange Hertz ladders for scale. Adds the
/// chart to `charts`; returns "" or the chart's failure.
std::string chart_accuracy(const std::string& out, const std::vector<BenchRow>& rows,
                           std::vector<ReportChart>& charts);

}  // namespace c2d::app
