#include "app/studies/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "app/report/gnuplot.hpp"
#include "app/report/units.hpp"
#include "app/report/html_report.hpp"
#include "app/studies/job_list.hpp"
#include "core/errors.hpp"
#include "core/scene.hpp"
#include "core/writers.hpp"

namespace fs = std::filesystem;

namespace c2d::app {

std::vector<double> parse_range(const std::string& spec, const std::string& where) {
  auto number = [&](const std::string& t) {
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (t.empty() || *end != '\0' || !std::isfinite(v))
      throw InputError(where + ": expected a number, found '" + t + "'");
    return v;
  };
  std::vector<std::string> parts;
  std::stringstream ss(spec);
  for (std::string p; std::getline(ss, p, ':');) parts.push_back(p);
  std::vector<double> values;
  if (parts.size() == 4) {
    const double a = number(parts[0]), b = number(parts[1]);
    const double n = number(parts[3]);
    if (n < 2 || n > 1000 || n != std::floor(n))
      throw InputError(where + ": expected a count from 2 to 1000 after the last ':', found '" +
                       parts[3] + "'");
    if (parts[2] == "log") {
      if (!(a > 0 && b > 0))
        throw InputError(where + ": a log range needs positive ends, found " + parts[0] + " and " +
                         parts[1]);
      for (int i = 0; i < n; ++i) values.push_back(a * std::pow(b / a, i / (n - 1)));
    } else if (parts[2] == "lin") {
      for (int i = 0; i < n; ++i) values.push_back(a + (b - a) * i / (n - 1));
    } else {
      throw InputError(where + ": expected 'log' or 'lin' as the range's third field, found '" +
                       parts[2] + "'");
    }
  } else if (parts.size() == 1) {
    std::stringstream list(spec);
    for (std::string v; std::getline(list, v, ',');) values.push_back(number(v));
    if (values.size() < 2)
      throw InputError(where +
                       ": expected a range a:b:log:n, a:b:lin:n or a list v1,v2,..., found '" +
                       spec + "'");
  } else {
    throw InputError(where +
                     ": expected a range a:b:log:n, a:b:lin:n or a list v1,v2,..., found '" + spec +
                     "'");
  }
  return values;
}

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

struct SweepRow : RunFigures {
  double value = 0.0;
};

std::string sweep_csv(const std::string& key, const std::vector<SweepRow>& rows) {
  std::ostringstream os;
  os << "value,key,status,exit_code,dofs,iterations,time_solve,p_max,error_p_max,"
        "max_penetration,total_force,pivot_ratio,penalty_max,stiffness_max\n";
  for (const auto& r : rows) {
    if (!r.done) continue;
    os << cell(r.value) << ',' << key << ',' << r.csv_status() << ',' << r.exit_code << ','
       << cell(r.dofs) << ',' << cell(r.iterations) << ',' << cell(r.t_solve) << ','
       << cell(r.p_max) << ',' << cell(r.err_p0) << ',' << cell(r.penetration) << ','
       << cell(r.force) << ',' << cell(r.pivot) << ',' << cell(r.penalty) << ','
       << cell(r.stiffness_max) << '\n';
  }
  return os.str();
}

/// The one ranged --set of a sweep and the fixed overrides beside it.
struct SweptKey {
  std::string key, spec;
  std::vector<std::string> fixed;
};

/// Whether a --set value is a sweep's range: a list of numbers v1,v2,... or a:b:SCALE:n (a value
/// with three ':' is taken as a range, so a mistyped one is reported as such). Anything else,
/// a title "Hertz, fine" or "a:b", a quoted string, an array [1.0, 2.0], is a fixed --set; before,
/// any ',' or ':' made a second swept key.
bool is_range(const std::string& value) {
  if (std::count(value.begin(), value.end(), ':') == 3) return true;
  try {
    parse_range(value, "");
    return true;
  } catch (const InputError&) {
    return false;
  }
}

SweptKey swept_key(const std::vector<std::string>& sets) {
  SweptKey k;
  for (const auto& s : sets) {
    const auto eq = s.find('=');
    const std::string value = eq == std::string::npos ? "" : s.substr(eq + 1);
    if (!is_range(value)) {
      k.fixed.push_back(s);
      continue;
    }
    if (!k.key.empty())
      throw InputError("--set " + s + ": a sweep varies one key; '" + k.key + "' is already swept");
    k.key = s.substr(0, eq);
    k.spec = value;
  }
  if (k.key.empty())
    throw InputError(
        "sweep: expected one --set key=a:b:log:n (or a:b:lin:n, or v1,v2,...), found none");
  return k;
}

/// The cases of a sweep, caseK in the study folder, the scene by its absolute path.
std::vector<StudyCase> sweep_cases(const SweepOptions& o, const SweptKey& k,
                                   const std::vector<double>& values) {
  const std::string scene = fs::absolute(o.scene).lexically_normal().string();
  std::vector<StudyCase> cases;
  for (size_t i = 0; i < values.size(); ++i) {
    StudyCase c;
    c.folder = "case" + std::to_string(i);
    c.args = {scene};
    if (!o.method.empty()) c.args.insert(c.args.end(), {"--method", o.method});
    for (const auto& s : k.fixed) c.args.insert(c.args.end(), {"--set", s});
    c.args.insert(c.args.end(), {"--set", k.key + "=" + cell(values[i])});
    cases.push_back(c);
  }
  return cases;
}

/// What the steps of a sweep share: the scene (as given, for titles), the swept key, the
/// accuracy asked for, how its times were taken, the cases and their rows (same order).
struct SweepStudy {
  std::string scene, key, out, timing;
  std::string units;  ///< the scene's `units` (the penetration panel's label)
  double accuracy = 0.01;
  double case_timeout_s = 0;  ///< the per-case limit (for the job list; 0: none)
  std::vector<StudyCase> cases;
  std::vector<SweepRow> rows;
};

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

/// The verdict paragraph: the range that converges and meets the accuracy, the failed values
/// grouped by their status word (the full messages are in the table), where the seed's rule
/// falls.
std::string sweep_verdict(double accuracy, const std::string& key,
                          const std::vector<SweepRow>& rows, const SeedRule& seed) {
  std::ostringstream md;
  double lo = std::nan(""), hi = std::nan("");
  bool has_error = false;
  bool any = false;
  for (const auto& r : rows) {
    any = any || r.done;
    has_error = has_error || std::isfinite(r.err_p0);
    if (r.converged() && std::isfinite(r.err_p0) && std::abs(r.err_p0) <= accuracy) {
      lo = std::isfinite(lo) ? std::min(lo, r.value) : r.value;
      hi = std::isfinite(hi) ? std::max(hi, r.value) : r.value;
    }
  }
  if (!any) return "No case has finished yet.";
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
    md << "The scene has no p_max reference, so no accuracy range is reported. ";
  else if (std::isfinite(lo))
    md << "Converged with |p_max error| <= " << percent_text(accuracy, 2) << " for " << key
       << " from " << cell(lo) << " to " << cell(hi) << " (of the values swept). ";
  else
    md << "No swept value met |p_max error| <= " << percent_text(accuracy, 2) << ". ";
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

std::string sweep_table(const std::string& key, const std::vector<SweepRow>& rows) {
  std::ostringstream md;
  md << "| " << key
     << " | status | iterations | solve | p_max | p_max error | max penetration | "
        "pivot ratio |\n|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows)
    if (r.done)
      md << "| " << cell(r.value) << " | " << r.status << " | " << cell(r.iterations) << " | "
         << seconds_text(r.t_solve) << " | " << cell(r.p_max) << " | " << percent_text(r.err_p0)
         << " | " << cell(r.penetration) << " | " << cell(r.pivot) << " |\n";
  return md.str();
}

/// sweep.png/svg: five panels against the swept value (the x range of sweep_x_range), failed
/// values as red dashed lines, the seed rule's k as a blue dotted one (told apart by their
/// dashes too, for a reader who does not see red from green);
/// nothing when no value converged. Returns "" or the chart's failure; `drawn` says whether
/// there was anything to draw.
std::string chart_sweep(const std::string& out, const std::string& key, const std::string& units,
                        const std::vector<SweepRow>& rows, const SeedRule& seed, bool& drawn) {
  std::ostringstream data;
  data << std::setprecision(12);
  bool has_error = false, has_pivot = false, log_x = true;
  for (const auto& r : rows) {
    has_error = has_error || std::isfinite(r.err_p0);
    // gnuplot refuses a panel without a point (a nonlinear run reports no pivot ratio).
    has_pivot = has_pivot || (r.converged() && std::isfinite(r.pivot));
    log_x = log_x && r.value > 0;
    if (r.converged())
      data << r.value << ' ' << std::max(std::abs(r.err_p0), 1e-12) << ' '
           << std::max(r.penetration, 1e-20) << ' ' << r.iterations << ' ' << r.t_solve << ' '
           << (std::isfinite(r.pivot) ? std::max(r.pivot, 1e-30) : std::nan("")) << '\n';
  }
  const std::string data_path = out + "/sweep.dat";
  std::vector<double> swept;
  for (const auto& r : rows)
    if (r.done) swept.push_back(r.value);
  const auto [x_lo, x_hi] = sweep_x_range(swept, seed.shown ? seed.k : std::nan(""), log_x);
  std::ostringstream plot;
  plot << std::setprecision(12) << "set multiplot layout 3,2 title "
       << gp_text(key + " sweep (red dashed: not converged" +
                  (seed.shown ? "; blue dotted: the seed rule 1e4 max|K_ij|" : "") + ")")
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
  if (has_error) panel(2, "|p_max error|", true);
  panel(3, axis_label("max penetration", parse_units(units).length), true);
  panel(4, "iterations", false);
  panel(5, "solve time (s)", false);
  if (has_pivot) panel(6, "pivot ratio (conditioning)", true);
  plot << "unset multiplot\n";
  drawn = !data.str().empty();
  return drawn ? plot_with_data(out, "sweep", plot.str(), {{data_path, data.str()}}) : "";
}

/// Validates the options against the scene (once, with the first value) and lays out a case per
/// value.
SweepStudy plan_sweep(const SweepOptions& o) {
  const SweptKey k = swept_key(o.sets);
  const std::vector<double> values = parse_range(k.spec, "--set " + k.key);
  std::vector<std::string> first = k.fixed;
  first.push_back(k.key + "=" + cell(values.front()));
  const std::string units = core::load_scene(o.scene, first).units;
  if (o.jobs < 1)
    throw InputError("--jobs: expected an integer >= 1, found " + std::to_string(o.jobs));
  SweepStudy s;
  s.scene = o.scene;
  s.key = k.key;
  s.accuracy = o.accuracy;
  s.units = units;
  s.out = study_out(o, "sweep");
  s.timing = timing_note(o.jobs);
  s.case_timeout_s = o.case_timeout_s;
  s.cases = sweep_cases(o, k, values);
  s.rows.resize(values.size());
  for (size_t i = 0; i < values.size(); ++i) s.rows[i].value = values[i];
  return s;
}

/// study.json's options and case keys: what the report needs besides the case folders.
void write_sweep_files(const SweepStudy& s) {
  const nlohmann::json options = {
      {"scene", s.scene}, {"key", s.key}, {"accuracy", s.accuracy}, {"units", s.units}};
  std::vector<nlohmann::json> keys;
  for (const auto& r : s.rows) keys.push_back({{"value", r.value}});
  write_study_files(s.out, "sweep", options, s.cases, keys, s.case_timeout_s);
}

SweepStudy sweep_from_manifest(const StudyManifest& m) {
  const ManifestNode options = m.options();
  SweepStudy s;
  s.scene = options["scene"].text();
  s.key = options["key"].text();
  if (options.has("units")) s.units = options["units"].text();
  s.accuracy = options["accuracy"].number();
  s.out = m.dir;
  s.timing = merged_timing_note();
  s.cases = m.cases;
  s.rows.resize(m.cases.size());
  for (size_t i = 0; i < m.cases.size(); ++i) s.rows[i].value = m.case_keys(i)["value"].number();
  return s;
}

/// sweep.csv, sweep.md, sweep.html and the chart from the finished rows, listing the `missing`
/// cases and those that timed out; the verdict on the terminal unless quiet. Returns 1 when a
/// case crashed, timed out or is missing or the chart failed, else 0.
int report_sweep(const SweepStudy& s, const std::vector<size_t>& missing, bool quiet) {
  const std::string csv = sweep_csv(s.key, s.rows);
  core::write_file_atomic(s.out + "/sweep.csv", csv);
  const SeedRule seed = seed_rule(s.key, s.rows);
  const std::string verdict = sweep_verdict(s.accuracy, s.key, s.rows, seed);
  bool drawn = false;
  const std::string chart_error = chart_sweep(s.out, s.key, s.units, s.rows, seed, drawn);
  ReportChart chart{
      "sweep", "p_max error, penetration, iterations, solve time and pivot ratio against " + s.key,
      chart_error};
  if (chart_error.empty() && !drawn)
    chart.not_written = "no swept value converged, so there is nothing to draw";
  const std::string title = "contact2d sweep: " + s.key + " on " + s.scene;
  const std::string timing = s.timing + "\n\n";
  const std::string unfinished =
      missing_cases_md(s.cases, missing) + timed_out_cases_md(s.cases, figures_of(s.rows));
  core::write_file_atomic(s.out + "/sweep.md",
                          "# " + title + "\n\n" + verdict + "\n\n" + unfinished + timing +
                              sweep_table(s.key, s.rows) +
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
  return any_case_failed(figures_of(s.rows)) || !missing.empty() || !chart_error.empty() ? 1 : 0;
}

}  // namespace

int run_sweep(const SweepOptions& o) {
  SweepStudy s = plan_sweep(o);
  if (o.job_list) refuse_existing_cases(s.out, s.cases);
  write_sweep_files(s);
  if (o.job_list) {
    if (!o.quiet) std::cout << job_list_note(s.out, s.cases.size(), o.case_timeout_s);
    return 0;
  }
  if (!o.quiet)
    std::cout << "sweep      " << s.key << " over " << s.rows.size() << " values ("
              << cell(s.rows.front().value) << " .. " << cell(s.rows.back().value) << "), "
              << o.jobs << " at a time -> " << s.out << "\n";
  size_t finished = 0;
  run_cases(s.cases, s.out, o.jobs, o.case_timeout_s, [&](size_t i, const CaseOutcome& c) {
    SweepRow& r = s.rows[i];
    r.read(c);
    ++finished;
    core::write_file_atomic(s.out + "/sweep.csv", sweep_csv(s.key, s.rows));
    if (!o.quiet)
      std::cout << "[" << finished << "/" << s.cases.size() << "] " << s.key << " = " << std::left
                << std::setw(12) << cell(r.value) << std::right << r.status
                << (r.timed_out() ? " after " + seconds_text(r.wall) : std::string())
                << (std::isfinite(r.err_p0) ? ", p_max error " + percent_text(r.err_p0)
                                            : std::string())
                << (std::isfinite(r.penetration) ? ", penetration " + cell(r.penetration)
                                                 : std::string())
                << std::endl;
  });
  retime_cases(s.cases, s.out, o.jobs, o.case_timeout_s, timed_out_rows(s.rows), o.quiet,
               [&](size_t i, const RunFigures& f) { take_times(s.rows[i], f); });
  return report_sweep(s, {}, o.quiet);
}

int merge_sweep(const StudyManifest& m, bool quiet) {
  SweepStudy s = sweep_from_manifest(m);
  const std::vector<size_t> missing = read_finished_cases(
      s.cases, s.out, [&](size_t i, const CaseOutcome& c) { s.rows[i].read(c); });
  return report_sweep(s, missing, quiet);
}

}  // namespace c2d::app
