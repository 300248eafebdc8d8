#include "app/studies/studies.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "app/process.hpp"
#include "app/report/gnuplot.hpp"
#include "app/report/hertz.hpp"
#include "app/report/pressure_profile.hpp"
#include "constraints/constraint_strategy.hpp"
#include "constraints/contact_scene.hpp"
#include "core/errors.hpp"
#include "core/scene.hpp"
#include "core/writers.hpp"

namespace fs = std::filesystem;

namespace c2d::app {

// ---------------------------------------------------------------------------------------------
// Running cases

namespace {

CaseOutcome run_one(const std::string& exe, const StudyCase& c) {
  CaseOutcome out;
  fs::create_directories(c.out_dir);
  std::vector<std::string> args{"run"};
  args.insert(args.end(), c.args.begin(), c.args.end());
  const auto t0 = std::chrono::steady_clock::now();
  const ProcessOutcome run = run_process(exe, args, c.out_dir + "/stdout.log");
  if (run.started) out.exit_code = run.exit_code, out.peak_rss_mb = run.peak_rss_mb;
  out.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::ifstream in(c.out_dir + "/summary.json");
  if (in) {
    try {
      out.summary = nlohmann::json::parse(in);
      out.has_summary = true;
    } catch (const std::exception&) {
      out.has_summary = false;
    }
  }
  return out;
}

}  // namespace

void run_cases(const std::vector<StudyCase>& cases, int jobs,
               const std::function<void(size_t, const CaseOutcome&)>& on_done) {
  const std::string exe = fs::read_symlink("/proc/self/exe").string();
  std::atomic<size_t> next{0};
  std::mutex done_mutex;
  auto worker = [&] {
    for (size_t i = next++; i < cases.size(); i = next++) {
      const CaseOutcome outcome = run_one(exe, cases[i]);
      std::lock_guard<std::mutex> lock(done_mutex);
      on_done(i, outcome);
    }
  };
  const int threads = std::max(1, std::min<int>(jobs, static_cast<int>(cases.size())));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
}

double json_number(const nlohmann::json& j, std::initializer_list<const char*> path) {
  const nlohmann::json* node = &j;
  for (const char* key : path) {
    if (!node->is_object() || !node->contains(key)) return std::nan("");
    node = &(*node)[key];
  }
  return node->is_number() ? node->get<double>() : std::nan("");
}

std::string csv_number(double v, int digits) {
  if (!std::isfinite(v)) return "";
  std::ostringstream os;
  os << std::setprecision(digits) << v;
  return os.str();
}

std::string RunFigures::csv_status() const {
  std::string s = status;
  std::replace(s.begin(), s.end(), ',', ';');
  std::replace(s.begin(), s.end(), '"', '\'');
  std::replace(s.begin(), s.end(), '\n', ' ');
  return '"' + s + '"';
}

bool RunFigures::read(const CaseOutcome& c) {
  done = true;
  exit_code = c.exit_code;
  wall = c.wall_seconds;
  peak_rss_mb = c.peak_rss_mb;
  if (!c.has_summary) {
    status = "crashed (exit " + std::to_string(c.exit_code) + ", no summary.json)";
    return false;
  }
  const auto& s = c.summary;
  status = s.value("status", std::string("unknown"));
  dofs = json_number(s, {"mesh", "dofs"});
  iterations = json_number(s, {"contact", "iterations"});
  newton = json_number(s, {"newton_iterations"});
  t_mesh = json_number(s, {"time_s", "mesh"});
  t_assemble = json_number(s, {"time_s", "assemble"});
  t_solve = json_number(s, {"time_s", "solve"});
  t_total = json_number(s, {"time_s", "total"});
  pivot = json_number(s, {"contact", "pivot_ratio"});
  penalty = json_number(s, {"contact", "penalty_max"});
  stiffness_max = json_number(s, {"contact", "stiffness_max"});
  zz = json_number(s, {"error", "relative_error"});
  if (converged()) {  // a failed run's contact figures are zeros, not results
    p_max = json_number(s, {"contact", "p_max"});
    length = json_number(s, {"contact", "length"});
    force = json_number(s, {"contact", "total_force"});
    penetration = json_number(s, {"contact", "max_penetration"});
    err_p0 = json_number(s, {"reference", "relative_error", "p_max"});
    err_b = json_number(s, {"reference", "relative_error", "contact_length"});
  }
  return true;
}

// ---------------------------------------------------------------------------------------------
// Pressure profiles

namespace {

std::string cell(double v) { return csv_number(v); }

std::string percent(double v, int digits = 3) {
  if (!std::isfinite(v)) return "–";
  std::ostringstream os;
  os << std::setprecision(digits) << 100.0 * v << " %";
  return os.str();
}

std::string seconds(double v) {
  std::ostringstream os;
  os << std::setprecision(3) << v << " s";
  return os.str();
}

struct CompareRow : RunFigures {
  int level = 0;
  std::string method;
  double mesh_scale = 1.0;
  double err_profile = std::nan("");
  double fit_p0 = std::nan(""), fit_b = std::nan(""), err_fit_p0 = std::nan(""),
         err_fit_b = std::nan("");  ///< Hertz form fitted to the nodal pressures (Ceres)
  std::vector<std::pair<double, double>> profile;
};

const char* kCompareHeader =
    "level,method,mesh_scale,dofs,status,exit_code,iterations,newton_iterations,time_mesh,"
    "time_assemble,time_solve,time_total,wall,p_max,contact_length,total_force,max_penetration,"
    "error_p_max,error_contact_length,error_profile_l2,zz_error,fit_p0,fit_b,error_fit_p0,"
    "error_fit_b\n";

std::string compare_csv(const std::vector<CompareRow>& rows) {
  std::ostringstream os;
  os << kCompareHeader;
  for (const auto& r : rows) {
    if (!r.done) continue;
    os << r.level << ',' << r.method << ',' << cell(r.mesh_scale) << ',' << cell(r.dofs) << ','
       << r.csv_status() << ',' << r.exit_code << ',' << cell(r.iterations) << ',' << cell(r.newton)
       << ',' << cell(r.t_mesh) << ',' << cell(r.t_assemble) << ',' << cell(r.t_solve) << ','
       << cell(r.t_total) << ',' << cell(r.wall) << ',' << cell(r.p_max) << ','
       << cell(r.length) << ',' << cell(r.force) << ',' << cell(r.penetration) << ','
       << cell(r.err_p0) << ',' << cell(r.err_b) << ',' << cell(r.err_profile) << ','
       << cell(r.zz) << ',' << cell(r.fit_p0) << ',' << cell(r.fit_b) << ','
       << cell(r.err_fit_p0) << ',' << cell(r.err_fit_b) << '\n';
  }
  return os.str();
}

/// The accuracy a row reached on the study's metric (NaN when it has none).
double accuracy(const CompareRow& r, const std::string& metric) {
  if (!r.converged()) return std::nan("");
  if (metric == "profile") return r.err_profile;
  if (metric == "p_max") return std::abs(r.err_p0);
  return std::nan("");
}

std::string metric_name(const std::string& metric) {
  return metric == "profile" ? "relative L2 error of the pressure profile"
                             : "relative error of p_max";
}

/// The verdict, computed from the table: the accuracy every converged method reached, and who
/// got there fastest (solve time).
std::string verdict(const std::vector<CompareRow>& rows, const std::vector<std::string>& methods,
                    const std::string& metric) {
  std::ostringstream os;
  std::vector<std::string> failed;
  for (const auto& r : rows)
    if (!r.converged())
      failed.push_back(r.method + " at level " + std::to_string(r.level) + " (" + r.status + ")");
  if (metric.empty()) {
    os << "The scene has no Hertz or p_max reference, so accuracy cannot be measured; ";
    double best_t = 1e300;
    std::string best;
    for (const auto& r : rows)
      if (r.converged() && r.level == rows.back().level && r.t_solve < best_t)
        best_t = r.t_solve, best = r.method;
    if (!best.empty())
      os << "on the finest level the fastest converged method was " << best << " ("
         << seconds(best_t) << " solve).";
  } else {
    std::map<std::string, double> best;
    for (const auto& m : methods) {
      double e = 1e300;
      for (const auto& r : rows)
        if (r.method == m && std::isfinite(accuracy(r, metric))) e = std::min(e, accuracy(r, metric));
      if (e < 1e300) best[m] = e;
    }
    if (best.empty()) {
      os << "No method converged on any level.";
    } else {
      double target = 0.0;
      for (const auto& [m, e] : best) target = std::max(target, e);
      std::vector<std::tuple<double, std::string, const CompareRow*>> ranking;
      for (const auto& [m, e] : best) {
        const CompareRow* fastest = nullptr;
        for (const auto& r : rows)
          if (r.method == m && accuracy(r, metric) <= target * (1 + 1e-9) &&
              (!fastest || r.t_solve < fastest->t_solve))
            fastest = &r;
        ranking.emplace_back(fastest->t_solve, m, fastest);
      }
      std::sort(ranking.begin(), ranking.end());
      const CompareRow* w = std::get<2>(ranking.front());
      os << "Every method that converged reached a " << metric_name(metric) << " of "
         << percent(target) << "; the fastest to it was **" << w->method << "** ("
         << seconds(w->t_solve) << " solve, level " << w->level << ", "
         << static_cast<long>(w->dofs) << " DOFs)";
      for (size_t i = 1; i < ranking.size(); ++i) {
        const CompareRow* r = std::get<2>(ranking[i]);
        os << (i == 1 ? ", then " : ", ") << r->method << " (" << seconds(r->t_solve) << ", level "
           << r->level << ")";
      }
      std::string most = best.begin()->first;
      for (const auto& [m, e] : best)
        if (e < best[most]) most = m;
      if (best[most] > 0.99 * target)
        os << ". Their best errors agree within 1 %: on this case the methods differ in cost, "
              "not in accuracy.";
      else
        os << ". The smallest error, " << percent(best[most]) << ", was " << most << "'s.";
    }
  }
  if (!failed.empty()) {
    os << " Not converged: ";
    for (size_t i = 0; i < failed.size(); ++i) os << (i ? "; " : "") << failed[i];
    os << ".";
  }
  return os.str();
}

std::string compare_md(const CompareOptions& o, const std::vector<CompareRow>& rows,
                       const std::vector<std::string>& methods, const std::string& metric,
                       const std::string& charts) {
  std::ostringstream os;
  os << "# contact2d compare: " << o.scene << "\n\n" << verdict(rows, methods, metric) << "\n\n";
  os << "Times are the solve phase (contact iterations included), from each run's summary.json; "
     << "errors are against the scene's [reference].\n\n";
  os << "Fitted p0 and b: the Hertz form p0 √(1 − ((x − x0)/b)²) fitted to the nodal pressures "
        "(Ceres), a contact width that does not depend on where the nodes fall.\n\n";
  os << "| level | method | DOFs | status | iterations | solve | total | p_max | contact length | "
        "total force | max penetration | p_max error | length error | profile L2 error | "
        "fitted p0 | fitted b | fitted b error |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    if (!r.done) continue;
    os << "| " << r.level << " | " << r.method << " | " << cell(r.dofs) << " | " << r.status
       << " | " << cell(r.iterations) << " | " << seconds(r.t_solve) << " | "
       << seconds(r.t_total) << " | " << cell(r.p_max) << " | " << cell(r.length) << " | "
       << cell(r.force) << " | " << cell(r.penetration) << " | " << percent(r.err_p0) << " | "
       << percent(r.err_b) << " | " << percent(r.err_profile) << " | " << cell(r.fit_p0)
       << " | " << cell(r.fit_b) << " | " << percent(r.err_fit_b) << " |\n";
  }
  if (!charts.empty()) os << "\n" << charts;
  return os.str();
}

std::string chart_commands_accuracy(const std::string& dir, const std::vector<CompareRow>& rows,
                                    const std::vector<std::string>& methods,
                                    const std::string& metric) {
  std::ostringstream data, plot;
  int block = 0;
  plot << "set title "
       << gp_text("Accuracy against solve time (" + metric_name(metric) +
                  "; one point per refinement level)")
       << "\nset xlabel 'solve time (s)'\nset ylabel " << gp_text(metric_name(metric)) << "\nset logscale xy\nset grid\nset key outside right\nplot ";
  for (const auto& m : methods) {
    std::ostringstream block_data;
    int points = 0;
    for (const auto& r : rows) {
      const double e = accuracy(r, metric);
      if (r.method != m || !std::isfinite(e) || !(e > 0) || !(r.t_solve > 0)) continue;
      block_data << r.t_solve << ' ' << e << ' ' << r.level << '\n';
      ++points;
    }
    if (!points) continue;
    data << block_data.str() << "\n\n";
    plot << (block ? ", \\\n     " : "") << gp_file(dir + "/accuracy.dat") << " index " << block
         << " using 1:2 with linespoints pt 7 lw 2 title " << gp_text(m) << " noenhanced";
    ++block;
  }
  if (!block) return "";
  core::write_file_atomic(dir + "/accuracy.dat", data.str());
  return plot.str() + "\n";
}

}  // namespace

int run_compare(const CompareOptions& o) {
  const core::Scene scene = core::load_scene(o.scene, o.sets);
  if (constraints::parse_contact_scene(scene, "").empty() &&
      !(scene.explicit_model && !scene.explicit_model->gaps.empty()))
    throw InputError(o.scene + ": compare needs a scene with [[contact]] (found none)");
  std::vector<std::string> methods = o.methods;
  if (methods.empty()) methods = constraints::method_names();
  for (const auto& m : methods)
    if (std::find(constraints::method_names().begin(), constraints::method_names().end(), m) ==
        constraints::method_names().end()) {
      std::string all;
      for (const auto& n : constraints::method_names()) all += (all.empty() ? "" : ", ") + n;
      throw InputError("--methods: expected a comma-separated list of " + all + ", found '" + m + "'");
    }
  if (o.levels < 1 || o.levels > 8)
    throw InputError("--levels: expected an integer from 1 to 8, found " + std::to_string(o.levels));
  if (o.jobs < 1) throw InputError("--jobs: expected an integer >= 1, found " + std::to_string(o.jobs));
  const std::string out = o.out.empty() ? "out/compare_" + fs::path(o.scene).stem().string() : o.out;
  fs::create_directories(out);

  // The accuracy metric the scene's reference allows.
  const auto hertz = hertz_reference(scene);
  const std::string metric = hertz ? "profile" : scene.reference.count("p_max") ? "p_max" : "";

  std::vector<StudyCase> cases;
  std::vector<CompareRow> rows;
  for (int level = 0; level < o.levels; ++level) {
    const double scale = scene.analysis.mesh_scale / std::pow(2.0, level);
    for (const auto& m : methods) {
      StudyCase c;
      c.out_dir = out + "/level" + std::to_string(level) + "/" + m;
      c.args = {o.scene, "--method", m};
      for (const auto& s : o.sets) c.args.insert(c.args.end(), {"--set", s});
      c.args.insert(c.args.end(), {"--set", "analysis.mesh_scale=" + cell(scale), "--out",
                                   c.out_dir, "--quiet"});
      cases.push_back(c);
      CompareRow r;
      r.level = level;
      r.method = m;
      r.mesh_scale = scale;
      rows.push_back(r);
    }
  }
  if (!o.quiet)
    std::cout << "compare    " << methods.size() << " methods x " << o.levels << " levels = "
              << cases.size() << " runs, " << o.jobs << " at a time -> " << out << "\n";
  size_t finished = 0;
  bool crashed = false;
  run_cases(cases, o.jobs, [&](size_t i, const CaseOutcome& c) {
    CompareRow& r = rows[i];
    if (!r.read(c)) crashed = true;
    {
      if (r.converged()) {
        r.profile = read_pressure_profile(cases[i].out_dir);
        // The run computed it from its own nodes (summary.json); the profile is read for the
        // chart and the fit.
        if (hertz) r.err_profile = json_number(c.summary, {"reference", "relative_error", "pressure_profile_l2"});
        const HertzFit fit = hertz ? fit_hertz_profile(r.profile) : HertzFit{};
        if (fit.ok) {
          r.fit_p0 = fit.p0;
          r.fit_b = fit.b;
          if (hertz) {
            r.err_fit_p0 = fit.p0 / hertz->p0 - 1.0;
            r.err_fit_b = fit.b / hertz->b - 1.0;
          }
        }
      }
    }
    ++finished;
    core::write_file_atomic(out + "/compare.csv", compare_csv(rows));
    if (!o.quiet)
      std::cout << "[" << finished << "/" << cases.size() << "] level " << r.level << " "
                << std::left << std::setw(17) << r.method << std::right << r.status << ", "
                << cell(r.dofs) << " DOFs, solve " << seconds(r.t_solve)
                << (std::isfinite(r.err_profile) ? ", profile error " + percent(r.err_profile)
                                                 : std::string())
                << std::endl;
  });

  // Charts: accuracy against time, the finest level's pressure profiles, penetration.
  std::string charts, chart_error;
  if (!metric.empty()) {
    const std::string cmd = chart_commands_accuracy(out, rows, methods, metric);
    if (!cmd.empty()) {
      chart_error = plot_png_and_svg(out, "accuracy_time", cmd);
      fs::remove(out + "/accuracy.dat");
      if (chart_error.empty())
        charts += "![accuracy against time](accuracy_time.png)\n\n";
    }
  }
  {
    std::ostringstream plot;
    plot << "set title 'Contact pressure, level " << o.levels - 1
         << " (finest), every method'\nset xlabel 'position along the slave surface'\n"
         << "set ylabel 'pressure'\nset grid\nset key top right\n";
    if (hertz) {
      // The data's span within 1.6 half-widths of the centre (a half model shows one side).
      double lo = 1e300, hi = -1e300;
      for (const auto& r : rows)
        if (r.level == o.levels - 1)
          for (const auto& xp : r.profile) lo = std::min(lo, xp.first), hi = std::max(hi, xp.first);
      write_hertz_window(plot, *hertz, lo, hi);
      plot << "set key top left\n";
    }
    plot << "plot ";
    int n = 0;
    for (const auto& r : rows) {
      if (r.level != o.levels - 1 || r.profile.empty()) continue;
      std::ostringstream d;
      d << std::setprecision(12);
      for (const auto& [x, p] : r.profile) d << x << ' ' << p << '\n';
      const std::string path = out + "/profile_" + r.method + ".dat";
      core::write_file_atomic(path, d.str());
      plot << (n ? ", \\\n     " : "") << gp_file(path) << " using 1:2 with linespoints pt "
           << 4 + n << " ps 0.7 title " << gp_text(r.method) << " noenhanced";
      ++n;
    }
    if (hertz) {
      plot << (n ? ", \\\n     " : "");
      write_hertz_curve(plot, *hertz);
      plot << " with lines lw 2 lc rgb 'black' dt 2 title 'Hertz'";
    }
    plot << "\n";
    if (n && chart_error.empty()) {
      chart_error = plot_png_and_svg(out, "pressure_profiles", plot.str());
      if (chart_error.empty()) charts += "![pressure profiles](pressure_profiles.png)\n\n";
    }
    for (const auto& r : rows) fs::remove(out + "/profile_" + r.method + ".dat");
  }
  {
    std::ostringstream d, plot;
    int n = 0;
    plot << "set title 'Largest penetration per method (exact methods at round-off; 0 drawn at "
            "1e-20)'\n"
         << "set xlabel 'refinement level'\nset ylabel 'max penetration'\nset logscale y\n"
         << "set format y '10^{%L}'\nset grid\nset key outside right\nset xtics 1\nplot ";
    for (const auto& m : methods) {
      std::ostringstream block;
      int points = 0;
      for (const auto& r : rows)
        if (r.method == m && r.converged() && std::isfinite(r.penetration))
          block << r.level << ' ' << std::max(r.penetration, 1e-20) << '\n', ++points;
      if (!points) continue;
      d << block.str() << "\n\n";
      plot << (n ? ", \\\n     " : "") << gp_file(out + "/penetration.dat") << " index " << n
           << " using 1:2 with linespoints pt 7 lw 2 title " << gp_text(m) << " noenhanced";
      ++n;
    }
    plot << "\n";
    if (n && chart_error.empty()) {
      core::write_file_atomic(out + "/penetration.dat", d.str());
      chart_error = plot_png_and_svg(out, "penetration", plot.str());
      fs::remove(out + "/penetration.dat");
      if (chart_error.empty()) charts += "![penetration](penetration.png)\n";
    }
  }
  core::write_file_atomic(out + "/compare.md", compare_md(o, rows, methods, metric, charts));
  if (!o.quiet) {
    std::cout << "\n" << verdict(rows, methods, metric) << "\n\nwrote " << out
              << "/compare.csv, compare.md"
              << (charts.empty() ? "" : ", accuracy_time, pressure_profiles, penetration (.png/.svg)")
              << "\n";
    if (!chart_error.empty()) std::cout << "warning    chart not written: " << chart_error << "\n";
  }
  return crashed || !chart_error.empty() ? 1 : 0;
}

}  // namespace c2d::app

// ---------------------------------------------------------------------------------------------
// Sweep

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
      throw InputError(where + ": expected a range a:b:log:n, a:b:lin:n or a list v1,v2,..., found '" +
                       spec + "'");
  } else {
    throw InputError(where + ": expected a range a:b:log:n, a:b:lin:n or a list v1,v2,..., found '" +
                     spec + "'");
  }
  return values;
}

namespace {

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

}  // namespace

int run_sweep(const SweepOptions& o) {
  // The one ranged --set; the others are fixed overrides.
  std::string key, spec;
  std::vector<std::string> fixed;
  for (const auto& s : o.sets) {
    const auto eq = s.find('=');
    const std::string value = eq == std::string::npos ? "" : s.substr(eq + 1);
    const bool ranged = value.find(':') != std::string::npos ||
                        (value.find(',') != std::string::npos && value.find('[') == std::string::npos);
    if (!ranged) {
      fixed.push_back(s);
      continue;
    }
    if (!key.empty())
      throw InputError("--set " + s + ": a sweep varies one key; '" + key + "' is already swept");
    key = s.substr(0, eq);
    spec = value;
  }
  if (key.empty())
    throw InputError("sweep: expected one --set key=a:b:log:n (or a:b:lin:n, or v1,v2,...), found none");
  const std::vector<double> values = parse_range(spec, "--set " + key);
  // Validate the scene and the key once, with the first value.
  const core::Scene scene = [&] {
    std::vector<std::string> sets = fixed;
    sets.push_back(key + "=" + cell(values.front()));
    return core::load_scene(o.scene, sets);
  }();
  if (o.jobs < 1) throw InputError("--jobs: expected an integer >= 1, found " + std::to_string(o.jobs));
  const std::string out = o.out.empty() ? "out/sweep_" + fs::path(o.scene).stem().string() : o.out;
  fs::create_directories(out);
  std::vector<StudyCase> cases;
  std::vector<SweepRow> rows(values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    StudyCase c;
    c.out_dir = out + "/case" + std::to_string(i);
    c.args = {o.scene};
    if (!o.method.empty()) c.args.insert(c.args.end(), {"--method", o.method});
    for (const auto& s : fixed) c.args.insert(c.args.end(), {"--set", s});
    c.args.insert(c.args.end(),
                  {"--set", key + "=" + cell(values[i]), "--out", c.out_dir, "--quiet"});
    cases.push_back(c);
    rows[i].value = values[i];
  }
  if (!o.quiet)
    std::cout << "sweep      " << key << " over " << values.size() << " values ("
              << cell(values.front()) << " .. " << cell(values.back()) << "), " << o.jobs
              << " at a time -> " << out << "\n";
  size_t finished = 0;
  bool crashed = false;
  run_cases(cases, o.jobs, [&](size_t i, const CaseOutcome& c) {
    SweepRow& r = rows[i];
    if (!r.read(c)) crashed = true;
    ++finished;
    core::write_file_atomic(out + "/sweep.csv", sweep_csv(key, rows));
    if (!o.quiet)
      std::cout << "[" << finished << "/" << cases.size() << "] " << key << " = " << std::left
                << std::setw(12) << cell(r.value) << std::right << r.status
                << (std::isfinite(r.err_p0) ? ", p_max error " + percent(r.err_p0) : std::string())
                << (std::isfinite(r.penetration) ? ", penetration " + cell(r.penetration) : std::string())
                << std::endl;
  });

  // The range that converges and meets the accuracy; the seed's rule k = 1e4 max|K_ij|.
  std::ostringstream md;
  md << "# contact2d sweep: " << key << " on " << o.scene << "\n\n";
  double lo = std::nan(""), hi = std::nan("");
  bool has_error = false;
  for (const auto& r : rows) {
    has_error = has_error || std::isfinite(r.err_p0);
    if (r.converged() && std::isfinite(r.err_p0) && std::abs(r.err_p0) <= o.accuracy) {
      lo = std::isfinite(lo) ? std::min(lo, r.value) : r.value;
      hi = std::isfinite(hi) ? std::max(hi, r.value) : r.value;
    }
  }
  // Failed values grouped by their status word (the full messages are in the table).
  std::vector<std::string> failed;
  std::map<std::string, std::string> by_status;
  for (const auto& r : rows) {
    if (r.converged()) continue;
    std::string word = r.status;
    if (word.rfind("failed: ", 0) == 0) word = word.substr(8);
    word = word.substr(0, word.find(':'));
    auto& list = by_status[word];
    list += (list.empty() ? "" : ", ") + cell(r.value);
  }
  for (const auto& [word, list] : by_status) failed.push_back(list + " (" + word + ")");
  if (!has_error)
    md << "The scene has no p_max reference, so no accuracy range is reported. ";
  else if (std::isfinite(lo))
    md << "Converged with |p_max error| <= " << percent(o.accuracy, 2) << " for " << key << " from "
       << cell(lo) << " to " << cell(hi) << " (of the values swept). ";
  else
    md << "No swept value met |p_max error| <= " << percent(o.accuracy, 2) << ". ";
  if (!failed.empty()) {
    md << "Not converged: ";
    for (size_t i = 0; i < failed.size(); ++i) md << (i ? "; " : "") << failed[i];
    md << ". ";
  }
  double seed_k = std::nan("");
  const bool penalty_k = key.size() >= 9 && key.compare(key.size() - 9, 9, "penalty.k") == 0;
  for (const auto& r : rows)
    if (std::isfinite(r.stiffness_max)) seed_k = 1e4 * r.stiffness_max;
  if (penalty_k && std::isfinite(seed_k)) {
    const SweepRow* nearest = nullptr;
    for (const auto& r : rows)
      if (!nearest || std::abs(std::log(r.value / seed_k)) < std::abs(std::log(nearest->value / seed_k)))
        nearest = &r;
    md << "The seed's rule k = 1e4 x max|K_ij| gives k = " << cell(seed_k) << " here";
    if (std::isfinite(lo))
      md << ((seed_k >= lo && seed_k <= hi) ? ", inside" : ", outside") << " that range";
    md << "; the nearest swept value, " << cell(nearest->value) << ", " << nearest->status
       << (std::isfinite(nearest->err_p0) ? " with p_max error " + percent(nearest->err_p0) : std::string())
       << ".";
  }
  md << "\n\n| " << key << " | status | iterations | solve | p_max | p_max error | max penetration | "
                           "pivot ratio |\n|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows)
    md << "| " << cell(r.value) << " | " << r.status << " | " << cell(r.iterations) << " | "
       << seconds(r.t_solve) << " | " << cell(r.p_max) << " | " << percent(r.err_p0) << " | "
       << cell(r.penetration) << " | " << cell(r.pivot) << " |\n";

  // One figure, five panels against the swept value; failed values as red dashed lines.
  std::ostringstream data;
  data << std::setprecision(12);
  for (const auto& r : rows)
    if (r.converged())
      data << r.value << ' ' << std::max(std::abs(r.err_p0), 1e-12) << ' '
           << std::max(r.penetration, 1e-20) << ' ' << r.iterations << ' ' << r.t_solve << ' '
           << (std::isfinite(r.pivot) ? std::max(r.pivot, 1e-30) : std::nan("")) << '\n';
  const std::string data_path = out + "/sweep.dat";
  core::write_file_atomic(data_path, data.str());
  bool log_x = true;
  for (double v : values) log_x = log_x && v > 0;
  std::ostringstream marks;
  for (const auto& r : rows)
    if (!r.converged())
      marks << "set arrow from " << r.value << ", graph 0 to " << r.value
            << ", graph 1 nohead lc rgb 'red' dt 2 lw 1.5\n";
  if (penalty_k && std::isfinite(seed_k))
    marks << "set arrow from " << seed_k << ", graph 0 to " << seed_k
          << ", graph 1 nohead lc rgb '#1a9850' dt 3 lw 1.5\n";
  std::ostringstream plot;
  plot << "set multiplot layout 3,2 title "
       << gp_text(key + " sweep (red: not converged" +
                  (penalty_k && std::isfinite(seed_k) ? "; green: the seed rule 1e4 max|K_ij|" : "") +
                  ")")
       << " noenhanced\nset grid\nunset key\n" << (log_x ? "set logscale x\n" : "")
       << "set format x '10^{%L}'\n" << marks.str();
  auto panel = [&](int col, const std::string& label, bool log_y) {
    plot << (log_y ? "set logscale y\nset format y '10^{%L}'\n" : "unset logscale y\nset format y '%g'\n")
         << "set xlabel " << gp_text(key) << " noenhanced\nset ylabel " << gp_text(label)
         << " noenhanced\nplot " << gp_file(data_path) << " using 1:" << col << " with linespoints pt 7 lw 2\n";
  };
  if (has_error) panel(2, "|p_max error|", true);
  panel(3, "max penetration", true);
  panel(4, "iterations", false);
  panel(5, "solve time (s)", false);
  panel(6, "pivot ratio (conditioning)", true);
  plot << "unset multiplot\n";
  std::string chart_error;
  if (!data.str().empty()) chart_error = plot_png_and_svg(out, "sweep", plot.str());
  fs::remove(data_path);
  if (chart_error.empty() && !data.str().empty()) md << "\n![sweep](sweep.png)\n";
  core::write_file_atomic(out + "/sweep.md", md.str());
  if (!o.quiet) {
    std::stringstream summary(md.str());
    std::string line;
    std::getline(summary, line);
    std::getline(summary, line);
    std::getline(summary, line);
    std::cout << "\n" << line << "\n\nwrote " << out << "/sweep.csv, sweep.md, sweep.png/svg\n";
    if (!chart_error.empty()) std::cout << "warning    chart not written: " << chart_error << "\n";
  }
  return crashed || !chart_error.empty() ? 1 : 0;
}

}  // namespace c2d::app
