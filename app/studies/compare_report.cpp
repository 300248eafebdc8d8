#include "app/studies/compare_report.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <sstream>
#include <tuple>

#include "app/report/html_report.hpp"
#include "app/report/pressure_profile.hpp"
#include "core/writers.hpp"

namespace c2d::app {

namespace {

std::string cell(double v) { return csv_number(v); }

const char* kCompareHeader =
    "level,method,mesh_scale,dofs,status,exit_code,iterations,newton_iterations,time_mesh,"
    "time_assemble,time_solve,time_total,wall,p_max,contact_length,total_force,max_penetration,"
    "error_p_max,error_contact_length,error_profile_l2,zz_error,fit_p0,fit_b,error_fit_p0,"
    "error_fit_b,stick_length,tangential_force,error_stick_length,error_shear_profile_l2\n";

}  // namespace

std::string compare_csv(const std::vector<CompareRow>& rows) {
  std::ostringstream os;
  os << kCompareHeader;
  for (const auto& r : rows) {
    if (!r.done) continue;
    os << r.level << ',' << r.method << ',' << cell(r.mesh_scale) << ',' << cell(r.dofs) << ','
       << r.csv_status() << ',' << r.exit_code << ',' << cell(r.iterations) << ',' << cell(r.newton)
       << ',' << cell(r.t_mesh) << ',' << cell(r.t_assemble) << ',' << cell(r.t_solve) << ','
       << cell(r.t_total) << ',' << cell(r.wall) << ',' << cell(r.p_max) << ',' << cell(r.length)
       << ',' << cell(r.force) << ',' << cell(r.penetration) << ',' << cell(r.err_p0) << ','
       << cell(r.err_b) << ',' << cell(r.err_profile) << ',' << cell(r.zz) << ',' << cell(r.fit_p0)
       << ',' << cell(r.fit_b) << ',' << cell(r.err_fit_p0) << ',' << cell(r.err_fit_b) << ','
       << cell(r.stick_length) << ',' << cell(r.tangent_force) << ',' << cell(r.err_stick) << ','
       << cell(r.err_shear) << '\n';
  }
  return os.str();
}

namespace {

/// A metric without reference is judged against one run: the exact method's on the finest
/// level it converged (lagrange, else ssn, else the first method listed).
const CompareRow* metric_baseline(const CompareStudy& s) {
  if (s.metric.empty() || s.metric.reference) return nullptr;
  std::vector<std::string> order{"lagrange", "ssn"};
  order.insert(order.end(), s.methods.begin(), s.methods.end());
  for (const std::string& m : order) {
    const CompareRow* best = nullptr;
    for (const auto& r : s.rows)
      if (r.method == m && r.converged() && std::isfinite(r.metric) &&
          (!best || r.level > best->level))
        best = &r;
    if (best) return best;
  }
  return nullptr;
}

}  // namespace

double accuracy(const CompareStudy& s, const CompareRow& r) {
  if (!r.converged() || s.metric.empty()) return std::nan("");
  if (s.metric.reference) return std::abs(r.metric);
  const CompareRow* base = metric_baseline(s);
  if (!base || r.level == base->level) return std::nan("");
  return std::abs(relative_to(r.metric, base->metric));
}

std::string metric_name(const CompareStudy& s) {
  std::string name = s.metric.label();
  if (const CompareRow* base = metric_baseline(s))
    name += " (" + base->method + ", level " + std::to_string(base->level) + ")";
  return name;
}

namespace {

/// Against a baseline run: how far the other methods' values on the baseline's level are from
/// it, as a sentence ("" without a baseline or another method there).
std::string method_spread(const CompareStudy& s) {
  const CompareRow* base = metric_baseline(s);
  if (!base) return "";
  const CompareRow* widest = nullptr;
  double spread = 0.0;
  for (const auto& r : s.rows) {
    if (&r == base || r.level != base->level || !r.converged()) continue;
    const double d = std::abs(relative_to(r.metric, base->metric));
    if (std::isfinite(d) && (!widest || d > spread)) widest = &r, spread = d;
  }
  if (!widest) return "";
  return " On level " + std::to_string(base->level) + " the other methods' values are within " +
         percent_text(spread) + " of " + base->method + "'s (the widest: " + widest->method + ").";
}

/// The observed order of convergence of a method on the study's metric over its converged
/// levels (h ∝ mesh_scale).
ObservedOrder method_order(const CompareStudy& s, const std::string& method) {
  std::vector<std::pair<double, double>> points;
  for (const auto& r : s.rows)
    if (r.method == method) points.emplace_back(r.mesh_scale, accuracy(s, r));
  return observed_order(points);
}

/// The methods whose error does not converge under refinement, with why; they are not ranked
/// (their smallest error may be a lucky level's).
std::string untrusted_orders(const CompareStudy& s, std::vector<std::string>& trusted) {
  std::string list;
  for (const auto& m : s.methods) {
    const ObservedOrder q = method_order(s, m);
    if (q.points >= 2 && !q.flag.empty())
      list += (list.empty() ? "" : "; ") + m + " (order " + order_text(q.order) + ", " + q.flag + ")";
    else
      trusted.push_back(m);
  }
  return list;
}

/// The verdict, computed from the table: the metric, the accuracy every converged method whose
/// error converges reached, who got there fastest (solve time), and the methods whose error
/// does not converge under refinement.
std::string verdict(const CompareStudy& s) {
  const std::vector<CompareRow>& rows = s.rows;
  std::ostringstream os;
  std::vector<std::string> failed;
  int finest = -1;  // of the finished cases (a merge may lack some)
  for (const auto& r : rows) {
    if (!r.done) continue;
    finest = std::max(finest, r.level);
    if (!r.converged())
      failed.push_back(r.method + " at level " + std::to_string(r.level) + " (" + r.status + ")");
  }
  if (finest < 0) return "No case has finished yet.";
  if (s.metric.empty()) {
    os << "The scene has no reference and no --metric was given, so accuracy cannot be "
          "measured; ";
    double best_t = 1e300;
    std::string best;
    for (const auto& r : rows)
      if (r.converged() && r.level == finest && r.t_solve < best_t)
        best_t = r.t_solve, best = r.method;
    if (!best.empty())
      os << "on the finest level the fastest converged method was " << best << " ("
         << seconds_text(best_t) << " solve).";
  } else {
    os << "Judged by the " << metric_name(s) << " (" << s.metric.why << "). ";
    std::vector<std::string> ranked;
    const std::string untrusted = untrusted_orders(s, ranked);
    std::map<std::string, double> best;
    for (const auto& m : ranked) {
      double e = 1e300;
      for (const auto& r : rows)
        if (r.method == m && std::isfinite(accuracy(s, r))) e = std::min(e, accuracy(s, r));
      if (e < 1e300) best[m] = e;
    }
    if (best.empty()) {
      os << (untrusted.empty() ? "No method converged on any level."
                               : "No method's error converges under refinement on these levels, "
                                 "so no fastest method is named.");
    } else {
      double target = 0.0;
      for (const auto& [m, e] : best) target = std::max(target, e);
      std::vector<std::tuple<double, std::string, const CompareRow*>> ranking;
      for (const auto& [m, e] : best) {
        const CompareRow* fastest = nullptr;
        for (const auto& r : rows)
          if (r.method == m && accuracy(s, r) <= target * (1 + 1e-9) &&
              (!fastest || r.t_solve < fastest->t_solve))
            fastest = &r;
        ranking.emplace_back(fastest->t_solve, m, fastest);
      }
      std::sort(ranking.begin(), ranking.end());
      const CompareRow* w = std::get<2>(ranking.front());
      os << "Every method ranked reached " << percent_text(target) << "; the fastest to it was **"
         << w->method << "** (" << seconds_text(w->t_solve) << " solve, level " << w->level
         << ", " << static_cast<long>(w->dofs) << " DOFs)";
      for (size_t i = 1; i < ranking.size(); ++i) {
        const CompareRow* r = std::get<2>(ranking[i]);
        os << (i == 1 ? ", then " : ", ") << r->method << " (" << seconds_text(r->t_solve)
           << ", level " << r->level << ")";
      }
      std::string most = best.begin()->first;
      for (const auto& [m, e] : best)
        if (e < best[most]) most = m;
      if (best[most] > 0.99 * target)
        os << ". Their best errors agree within 1 %: on this case the methods differ in cost, "
              "not in accuracy.";
      else
        os << ". The smallest error, " << percent_text(best[most]) << ", was " << most << "'s.";
    }
    os << method_spread(s);
    if (!untrusted.empty())
      os << " **Not ranked**, their error does not converge under refinement (a smallest error "
            "could be a lucky level's): "
         << untrusted << ".";
  }
  if (!failed.empty()) {
    os << " Not converged: ";
    for (size_t i = 0; i < failed.size(); ++i) os << (i ? "; " : "") << failed[i];
    os << ".";
  }
  return os.str();
}

/// orders.csv and compare.md's table: one line per method, with why an order is not trusted.
std::string orders_csv(const CompareStudy& s) {
  std::ostringstream os;
  os << "method,metric,order,flag\n";
  for (const auto& m : s.methods) {
    const ObservedOrder q = method_order(s, m);
    os << m << ',' << s.metric.key << ',' << cell(q.order) << ",\"" << q.flag << "\"\n";
  }
  return os.str();
}

std::string orders_md(const CompareStudy& s) {
  if (s.metric.empty()) return "";
  std::ostringstream os;
  os << "Observed order of convergence (slope of log " << metric_name(s)
     << " against log h over the converged levels; each level halves every element size, the "
        "graded zone's included):\n\n| method | order | level to level | note |\n"
        "|---|---|---|---|\n";
  for (const auto& m : s.methods) {
    const ObservedOrder q = method_order(s, m);
    os << "| " << m << " | " << order_text(q.order) << " | "
       << (q.points >= 3 ? order_text(q.low) + " to " + order_text(q.high) : "–") << " | "
       << (q.flag.empty() ? "" : "**" + q.flag + "**") << " |\n";
  }
  return os.str() + "\n";
}

std::string compare_title(const CompareStudy& s) { return "contact2d compare: " + s.scene; }

/// How the times and errors were taken: under the title of compare.md and compare.html.
std::string times_note(const CompareStudy& s) {
  return "Times are the solve phase (contact iterations included), from each run's "
         "summary.json; errors are against the scene's [reference]. " +
         s.timing + "\n\n";
}

const char* const kFitNote =
    "Fitted p0 and b: the Hertz form p0 √(1 − ((x − x0)/b)²) fitted to the nodal pressures "
    "(Ceres), a contact width that does not depend on where the nodes fall.\n\n";

std::string compare_md(const CompareStudy& s, const std::vector<size_t>& missing,
                       const std::string& charts) {
  const std::vector<CompareRow>& rows = s.rows;
  std::ostringstream os;
  os << "# " << compare_title(s) << "\n\n"
     << verdict(s) << "\n\n"
     << missing_cases_md(s.cases, missing) << timed_out_cases_md(s.cases, figures_of(rows))
     << orders_md(s) << times_note(s) << kFitNote;
  os << "| level | method | DOFs | status | iterations | solve | total | p_max | contact length | "
        "total force | max penetration | p_max error | length error | profile L2 error | "
        "fitted p0 | fitted b | fitted b error |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    if (!r.done) continue;
    os << "| " << r.level << " | " << r.method << " | " << cell(r.dofs) << " | " << r.status
       << " | " << cell(r.iterations) << " | " << seconds_text(r.t_solve) << " | "
       << seconds_text(r.t_total) << " | " << cell(r.p_max) << " | " << cell(r.length) << " | "
       << cell(r.force) << " | " << cell(r.penetration) << " | " << percent_text(r.err_p0) << " | "
       << percent_text(r.err_b) << " | " << percent_text(r.err_profile) << " | " << cell(r.fit_p0)
       << " | " << cell(r.fit_b) << " | " << percent_text(r.err_fit_b) << " |\n";
  }
  if (!charts.empty()) os << "\n" << charts;
  return os.str();
}

/// compare.html: the same title, notes and verdict as compare.md, compare.csv's every column,
/// the charts inline.
HtmlReport compare_html(const CompareStudy& s, const std::vector<size_t>& missing,
                        const std::vector<ReportChart>& charts) {
  HtmlReport h;
  h.title = compare_title(s);
  h.intro_md = times_note(s);
  h.verdict_md = verdict(s);
  h.notes_md = missing_cases_md(s.cases, missing) +
               timed_out_cases_md(s.cases, figures_of(s.rows)) +
               orders_md(s) + (s.hertz ? kFitNote : "");
  h.csv_name = "compare.csv";
  h.csv = compare_csv(s.rows);
  // What a reader compares first: each case's errors against the reference, then its times;
  // the status (long when a run failed) and the raw figures after.
  h.lead_columns = {"level",
                    "method",
                    "dofs",
                    "error_p_max",
                    "error_contact_length",
                    "error_profile_l2",
                    "error_fit_p0",
                    "error_fit_b",
                    "error_stick_length",
                    "error_shear_profile_l2",
                    "time_solve",
                    "time_total",
                    "status"};
  h.charts = charts;
  return h;
}

}  // namespace

/// A finished case's row: its figures, and for a converged run its pressure profile, with the
/// Hertz form fitted to it. False when the case left no summary (a crash).
bool read_row(CompareRow& r, const CaseOutcome& c, const std::string& dir,
              const CompareStudy& s) {
  if (!r.read(c)) return false;
  if (!r.converged()) return true;
  if (!s.metric.empty()) r.metric = metric_reading(c.summary, s.metric);
  const std::optional<HertzReference>& hertz = s.hertz;
  r.profile = read_pressure_profile(dir);
  // The run computed it from its own nodes (summary.json); the profile is read for the chart
  // and the fit.
  if (!hertz) return true;
  r.err_profile = json_number(c.summary, {"reference", "relative_error", "pressure_profile_l2"});
  const HertzFit fit = fit_hertz_profile(r.profile);
  if (fit.ok) {
    r.fit_p0 = fit.p0;
    r.fit_b = fit.b;
    r.err_fit_p0 = fit.p0 / hertz->p0 - 1.0;
    r.err_fit_b = fit.b / hertz->b - 1.0;
  }
  return true;
}

int report_compare(const CompareStudy& s, const std::vector<size_t>& missing, bool quiet) {
  core::write_file_atomic(s.out + "/compare.csv", compare_csv(s.rows));
  std::vector<ReportChart> charts;
  const std::string chart_error = draw_compare_charts(s, charts);
  core::write_file_atomic(s.out + "/compare.md", compare_md(s, missing, markdown_images(charts)));
  write_html_report(s.out, "compare.html", compare_html(s, missing, charts));
  if (!s.metric.empty())
    core::write_file_atomic(s.out + "/orders.csv", orders_csv(s));
  if (!quiet) {
    std::string drawn;
    for (const auto& c : charts)
      if (c.written()) drawn += ", " + c.stem;
    std::cout << "\n"
              << verdict(s) << "\n\n"
              << missing_cases_text(s.cases, missing)
              << timed_out_cases_text(s.cases, figures_of(s.rows))
              << orders_md(s) << "wrote " << s.out
              << "/compare.csv, compare.md, compare.html"
              << (s.metric.empty() ? "" : ", orders.csv")
              << (drawn.empty() ? "" : drawn + " (.png/.svg)") << "\n";
    if (!chart_error.empty()) std::cout << "warning    chart not written: " << chart_error << "\n";
  }
  return any_case_failed(figures_of(s.rows)) || !missing.empty() || !chart_error.empty() ? 1 : 0;
}

}  // namespace c2d::app
