#include "app/studies/sweep_report.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "app/report/gnuplot.hpp"
#include "app/report/html_report.hpp"
#include "app/report/units.hpp"
#include "app/studies/sweep.hpp"
#include "core/writers.hpp"

namespace c2d::app {

std::pair<double, double> sweep_x_range(std::vector<double> values, double seed_k, bool log_x) {
  if (std::isfinite(seed_k)) values.push_back(seed_k);
  if (values.empty()) return {std::nan(""), std::nan("")};
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  if (log_x)
    return {std::pow(10.0, std::floor(std::log10(*lo) - 0.1)),
            std::pow(10.0, std::ceil(std::log10(*hi) + 0.1))};
  const double margin = 0.05 * (*hi > *lo ? *hi - *lo : std::max(std::abs(*lo), 1.0));
  return {*lo - margin, *hi + margin};
}

namespace {

std::string cell(double v) { return csv_number(v); }

bool is_profile(const std::string& key) {
  return key == "pressure_profile_l2" || key == "pressure_profile_inner_l2" ||
         key == "shear_profile_l2";
}

/// A row's metric against the baseline's (the regularisation's own error, the mesh's taken
/// out): relative difference of the values, of (1 + relative error) for a reference figure,
/// the excess L2 error for a profile; NaN without a converged baseline.
double own_error(const SweepStudy& s, const SweepRow& r) {
  if (s.baseline_method.empty() || !s.baseline.converged() || !r.converged()) return std::nan("");
  const double b = s.baseline.metric, v = r.metric;
  if (!s.metric.reference) return relative_to(v, b);
  return is_profile(s.metric.key) ? v - b : relative_to(1 + v, 1 + b);
}

/// What a row is judged by against the accuracy: its reference error, else its own error.
double judged_error(const SweepStudy& s, const SweepRow& r) {
  if (!r.converged() || s.metric.empty()) return std::nan("");
  return std::abs(s.metric.reference ? r.metric : own_error(s, r));
}

/// "|p_max error|", or "|tip / lagrange's - 1|".
std::string judged_name(const SweepStudy& s) {
  if (s.metric.reference) return "|" + s.metric.key + " error|";
  return "|" + s.metric.key + " / " + s.baseline_method + "'s - 1|";
}

/// The seed's rule k = 1e4 max|K_ij|, shown when the swept key is a penalty stiffness and a run
/// reported max|K_ij|.
struct SeedRule {
  bool shown = false;
  double k = std::nan("");
};

SeedRule seed_rule(const std::string& key, const std::vector<SweepRow>& rows) {
  SeedRule rule;
  const bool penalty_k = key.size() >= 9 && key.compare(key.size() - 9, 9, "penalty.k") == 0;
  for (const auto& r : rows)
    if (std::isfinite(r.stiffness_max)) rule.k = 1e4 * r.stiffness_max;
  rule.shown = penalty_k && std::isfinite(rule.k);
  return rule;
}

/// The swept values whose `error` meets the accuracy: [lo, hi] (NaN when none).
std::pair<double, double> accurate_range(const SweepStudy& s,
                                         double (*error)(const SweepStudy&, const SweepRow&)) {
  double lo = std::nan(""), hi = std::nan("");
  for (const auto& r : s.rows) {
    const double e = std::abs(error(s, r));
    if (r.converged() && std::isfinite(e) && e <= s.accuracy) {
      lo = std::isfinite(lo) ? std::min(lo, r.value) : r.value;
      hi = std::isfinite(hi) ? std::max(hi, r.value) : r.value;
    }
  }
  return {lo, hi};
}

/// The baseline's sentence: its own reading, and the values within the accuracy of it.
std::string baseline_verdict(const SweepStudy& s) {
  if (s.baseline_method.empty()) return "";
  if (!s.baseline.done) return "The baseline (" + s.baseline_method + ") has not finished. ";
  if (!s.baseline.converged())
    return "The baseline (" + s.baseline_method + " on the same mesh) did not converge (" +
           s.baseline.status + "). ";
  if (!s.metric.reference)
    return "The baseline, " + s.baseline_method + " on the same mesh, gives " + s.metric.key +
           " = " + cell(s.baseline.metric) + ". ";
  std::ostringstream md;
  md << "Against " << s.baseline_method << " on the same mesh (exact: the discretisation's "
     << "error alone; its " << s.metric.key << " "
     << (s.metric.reference ? "error " + percent_text(s.baseline.metric)
                            : "= " + cell(s.baseline.metric))
     << "): ";
  const auto [lo, hi] = accurate_range(s, &own_error);
  if (std::isfinite(lo))
    md << "within " << percent_text(s.accuracy, 2) << " of it for " << s.key << " from "
       << cell(lo) << " to " << cell(hi) << ". ";
  else
    md << "no swept value came within " << percent_text(s.accuracy, 2) << " of it. ";
  return md.str();
}

/// The verdict paragraph: the metric, the range that converges and meets the accuracy (against
/// the reference, and against the baseline), the failed values grouped by their status word
/// (the full messages are in the table), where the seed's rule falls.
std::string sweep_verdict(const SweepStudy& s, const SeedRule& seed) {
  const std::vector<SweepRow>& rows = s.rows;
  const std::string& key = s.key;
  const double accuracy = s.accuracy;
  std::ostringstream md;
  bool any = false, has_error = false;
  for (const auto& r : rows) {
    any = any || r.done;
    has_error = has_error || std::isfinite(judged_error(s, r));
  }
  if (!any) return "No case has finished yet.";
  const auto [lo, hi] = accurate_range(s, &judged_error);
  md << "Judged by " << judged_name(s) << " (" << s.metric.why << "). ";
  std::map<std::string, std::string> by_status;
  for (const auto& r : rows) {
    if (!r.done || r.converged()) continue;
    std::string word = r.status;
    if (word.rfind("failed: ", 0) == 0) word = word.substr(8);
    word = word.substr(0, word.find(':'));
    auto& list = by_status[word];
    list += (list.empty() ? "" : ", ") + cell(r.value);
  }
  if (!has_error)
    md << "The scene has no reference for " << s.metric.key
       << " and there is no baseline, so no accuracy range is reported. ";
  else if (std::isfinite(lo))
    md << "Converged with " << judged_name(s) << " <= " << percent_text(accuracy, 2) << " for "
       << key << " from " << cell(lo) << " to " << cell(hi) << " (of the values swept). ";
  else
    md << "No swept value met " << judged_name(s) << " <= " << percent_text(accuracy, 2) << ". ";
  md << baseline_verdict(s);
  if (!by_status.empty()) {
    std::string failed;
    for (const auto& [word, list] : by_status)
      failed += (failed.empty() ? "" : "; ") + list + " (" + word + ")";
    md << "Not converged: " << failed << ". ";
  }
  if (seed.shown) {
    const SweepRow* nearest = nullptr;
    for (const auto& r : rows)
      if (r.done && (!nearest || std::abs(std::log(r.value / seed.k)) <
                                     std::abs(std::log(nearest->value / seed.k))))
        nearest = &r;
    md << "The seed's rule k = 1e4 x max|K_ij| gives k = " << cell(seed.k) << " here";
    if (std::isfinite(lo))
      md << ((seed.k >= lo && seed.k <= hi) ? ", inside" : ", outside") << " that range";
    md << "; the nearest swept value, " << cell(nearest->value) << ", " << nearest->status
       << (std::isfinite(nearest->err_p0) ? " with p_max error " + percent_text(nearest->err_p0)
                                          : std::string())
       << ".";
  }
  return md.str();
}

std::string sweep_table(const SweepStudy& s) {
  std::ostringstream md;
  md << "| " << s.key
     << " | status | iterations | solve | p_max | p_max error | max penetration | "
        "pivot ratio | " << s.metric.key << " |\n|---|---|---|---|---|---|---|---|---|\n";
  const auto line = [&](const std::string& first, const SweepRow& r) {
    md << "| " << first << " | " << r.status << " | " << cell(r.iterations) << " | "
       << seconds_text(r.t_solve) << " | " << cell(r.p_max) << " | " << percent_text(r.err_p0)
       << " | " << cell(r.penetration) << " | " << cell(r.pivot) << " | "
       << (s.metric.reference ? percent_text(r.metric) : cell(r.metric)) << " |\n";
  };
  for (const auto& r : s.rows)
    if (r.done) line(cell(r.value), r);
  if (s.baseline.done) line(s.baseline_method + " (baseline)", s.baseline);
  return md.str();
}

/// The metric panel's value of a row: |relative error| (log scale) for a reference metric, the
/// value itself otherwise.
double plotted_metric(const SweepStudy& s, const SweepRow& r) {
  return s.metric.reference ? std::max(std::abs(r.metric), 1e-12) : r.metric;
}

/// sweep.png/svg: five panels against the swept value (the x range of sweep_x_range; the
/// metric's with the baseline as a black dashed line), failed values as red dashed lines, the
/// seed rule's k as a blue dotted one (told apart by their dashes too, for a reader who does
/// not see red from green); nothing when no value converged. Returns "" or the chart's
/// failure; `drawn` says whether there was anything to draw.
std::string chart_sweep(const SweepStudy& s, const SeedRule& seed, bool& drawn) {
  const std::string& key = s.key;
  const std::vector<SweepRow>& rows = s.rows;
  std::ostringstream data;
  data << std::setprecision(12);
  bool has_metric = false, has_pivot = false, log_x = true;
  for (const auto& r : rows) {
    has_metric = has_metric || (r.converged() && std::isfinite(r.metric));
    // gnuplot refuses a panel without a point (a nonlinear run reports no pivot ratio).
    has_pivot = has_pivot || (r.converged() && std::isfinite(r.pivot));
    log_x = log_x && r.value > 0;
    if (r.converged())
      data << r.value << ' ' << plotted_metric(s, r) << ' ' << std::max(r.penetration, 1e-20)
           << ' ' << r.iterations << ' ' << r.t_solve << ' '
           << (std::isfinite(r.pivot) ? std::max(r.pivot, 1e-30) : std::nan("")) << '\n';
  }
  const bool baseline = s.baseline.converged() && std::isfinite(s.baseline.metric);
  const std::string data_path = s.out + "/sweep.dat";
  std::vector<double> swept;
  for (const auto& r : rows)
    if (r.done) swept.push_back(r.value);
  const auto [x_lo, x_hi] = sweep_x_range(swept, seed.shown ? seed.k : std::nan(""), log_x);
  std::ostringstream plot;
  plot << std::setprecision(12) << "set multiplot layout 3,2 title "
       << gp_text(key + " sweep (red dashed: not converged" +
                  (seed.shown ? "; blue dotted: the seed rule 1e4 max|K_ij|" : "") +
                  (baseline ? "; black dashed: " + s.baseline_method + " on the same mesh" : "") +
                  ")")
       << "\nset grid\nunset key\n"
       << (log_x ? "set logscale x\nset format x '10^{%L}'\n" : "set format x '%g'\n")
       << "set xrange [" << x_lo << ":" << x_hi << "]\n";
  for (const auto& r : rows)
    if (r.done && !r.converged())
      plot << "set arrow from " << r.value << ", graph 0 to " << r.value
           << ", graph 1 nohead lc rgb '#d55e00' dt 2 lw 1.5\n";
  if (seed.shown)
    plot << "set arrow from " << seed.k << ", graph 0 to " << seed.k
         << ", graph 1 nohead lc rgb '#0072b2' dt 3 lw 2\n";
  auto panel = [&](int col, const std::string& label, bool log_y) {
    plot << (log_y ? "set logscale y\nset format y '10^{%L}'\n"
                   : "unset logscale y\nset format y '%g'\n")
         << "set xlabel " << gp_text(key) << "\nset ylabel " << gp_text(label) << "\nplot "
         << gp_file(data_path) << " using 1:" << col << " with linespoints pt 7 lw 2\n";
  };
  if (has_metric) {
    if (baseline)  // tag 100: this panel's only
      plot << "set arrow 100 from graph 0, first " << plotted_metric(s, s.baseline)
           << " to graph 1, first " << plotted_metric(s, s.baseline)
           << " nohead lc rgb 'black' dt 2 lw 1.5\n";
    panel(2, s.metric.reference ? "|" + s.metric.key + " error|" : s.metric.key,
          s.metric.reference);
    if (baseline) plot << "unset arrow 100\n";
  }
  panel(3, axis_label("max penetration", parse_units(s.units).length), true);
  panel(4, "iterations", false);
  panel(5, "solve time (s)", false);
  if (has_pivot) panel(6, "pivot ratio (conditioning)", true);
  plot << "unset multiplot\n";
  drawn = !data.str().empty();
  return drawn ? plot_with_data(s.out, "sweep", plot.str(), {{data_path, data.str()}}) : "";
}

}  // namespace

std::string sweep_csv(const SweepStudy& s) {
  std::ostringstream os;
  os << "value,key,status,exit_code,dofs,iterations,time_solve,p_max,error_p_max,"
        "max_penetration,total_force,pivot_ratio,penalty_max,stiffness_max,metric,metric_value,"
        "error_vs_baseline\n";
  for (const auto& r : s.rows) {
    if (!r.done) continue;
    os << cell(r.value) << ',' << s.key << ',' << r.csv_status() << ',' << r.exit_code << ','
       << cell(r.dofs) << ',' << cell(r.iterations) << ',' << cell(r.t_solve) << ','
       << cell(r.p_max) << ',' << cell(r.err_p0) << ',' << cell(r.penetration) << ','
       << cell(r.force) << ',' << cell(r.pivot) << ',' << cell(r.penalty) << ','
       << cell(r.stiffness_max) << ',' << s.metric.key << ',' << cell(r.metric) << ','
       << cell(own_error(s, r)) << '\n';
  }
  return os.str();
}

void read_sweep_row(const SweepStudy& s, SweepRow& r, const CaseOutcome& c) {
  r.read(c);
  if (r.converged()) r.metric = metric_reading(c.summary, s.metric);
}

int report_sweep(const SweepStudy& s, const std::vector<size_t>& missing, bool quiet) {
  const std::string csv = sweep_csv(s);
  core::write_file_atomic(s.out + "/sweep.csv", csv);
  const SeedRule seed = seed_rule(s.key, s.rows);
  const std::string verdict = sweep_verdict(s, seed);
  bool drawn = false;
  const std::string chart_error = chart_sweep(s, seed, drawn);
  ReportChart chart{"sweep",
                    s.metric.key + ", penetration, iterations, solve time and pivot ratio against " +
                        s.key,
                    chart_error};
  if (chart_error.empty() && !drawn)
    chart.not_written = "no swept value converged, so there is nothing to draw";
  const std::string title = "contact2d sweep: " + s.key + " on " + s.scene;
  const std::string timing = s.timing + "\n\n";
  const std::string unfinished =
      missing_cases_md(s.cases, missing) + timed_out_cases_md(s.cases, figures_of(s.rows));
  core::write_file_atomic(s.out + "/sweep.md",
                          "# " + title + "\n\n" + verdict + "\n\n" + unfinished + timing +
                              sweep_table(s) +
                              (chart.written() ? "\n" + markdown_images({chart}) : ""));
  write_html_report(s.out, "sweep.html",
                    {title, "", timing, verdict, unfinished, "sweep.csv", csv, {chart}, {}});
  if (!quiet) {
    std::cout << "\n"
              << verdict << "\n\n"
              << missing_cases_text(s.cases, missing)
              << timed_out_cases_text(s.cases, figures_of(s.rows)) << "wrote " << s.out
              << "/sweep.csv, sweep.md, sweep.html" << (chart.written() ? ", sweep.png/svg" : "")
              << "\n";
    if (!chart_error.empty()) std::cout << "warning    chart not written: " << chart_error << "\n";
  }
  std::vector<const RunFigures*> all = figures_of(s.rows);
  if (s.baseline.done) all.push_back(&s.baseline);
  return any_case_failed(all) || !missing.empty() || !chart_error.empty() ? 1 : 0;
}

}  // namespace c2d::app
