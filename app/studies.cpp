#include "app/studies.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

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

#include "app/charts.hpp"
#include "app/trace_charts.hpp"
#include "constraints/constraint_strategy.hpp"
#include "constraints/contact_scene.hpp"
#include "core/errors.hpp"
#include "core/scene.hpp"
#include "core/writers.hpp"

extern char** environ;

namespace fs = std::filesystem;

namespace c2d::app {

// ---------------------------------------------------------------------------------------------
// Running cases

namespace {

CaseOutcome run_one(const std::string& exe, const StudyCase& c) {
  CaseOutcome out;
  fs::create_directories(c.out_dir);
  std::vector<std::string> args{"contact2d", "run"};
  args.insert(args.end(), c.args.begin(), c.args.end());
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  const std::string log = c.out_dir + "/stdout.log";
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  const auto t0 = std::chrono::steady_clock::now();
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, exe.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc == 0) {
    int status = 0;
    if (waitpid(pid, &status, 0) == pid)
      out.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
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

// ---------------------------------------------------------------------------------------------
// Pressure profiles

double hertz_profile_error(const std::vector<std::pair<double, double>>& x_p, double p0, double b) {
  if (x_p.size() < 2 || !(b > 0) || !(p0 > 0)) return std::nan("");
  std::vector<std::pair<double, double>> pts = x_p;
  std::sort(pts.begin(), pts.end());
  const double lo = std::max(pts.front().first, -1.5 * b), hi = std::min(pts.back().first, 1.5 * b);
  if (!(hi > lo)) return std::nan("");
  constexpr int kSamples = 4000;
  double err2 = 0.0, ref2 = 0.0;
  size_t k = 0;
  for (int i = 0; i <= kSamples; ++i) {
    const double x = lo + (hi - lo) * i / kSamples;
    while (k + 2 < pts.size() && pts[k + 1].first < x) ++k;
    const auto& a = pts[k];
    const auto& c = pts[k + 1];
    const double t = c.first > a.first ? std::clamp((x - a.first) / (c.first - a.first), 0.0, 1.0) : 0.0;
    const double ph = a.second + t * (c.second - a.second);
    const double pa = std::abs(x) < b ? p0 * std::sqrt(1.0 - (x / b) * (x / b)) : 0.0;
    const double w = (i == 0 || i == kSamples) ? 0.5 : 1.0;
    err2 += w * (ph - pa) * (ph - pa);
    ref2 += w * pa * pa;
  }
  return ref2 > 0 ? std::sqrt(err2 / ref2) : std::nan("");
}

namespace {

/// Slave-node pressures of a finished run along the surface's main direction.
std::vector<std::pair<double, double>> read_profile(const std::string& dir) {
  std::vector<std::pair<double, double>> pts;
  if (!fs::exists(dir + "/contact.csv")) return pts;
  const CsvTable t = read_csv(dir + "/contact.csv");
  const int cx = t.column("x"), cy = t.column("y"), cp = t.column("pressure");
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (size_t r = 0; r < t.rows.size(); ++r)
    for (int k = 0; k < 2; ++k) {
      const double v = t.number(r, k == 0 ? cx : cy);
      lo[k] = std::min(lo[k], v), hi[k] = std::max(hi[k], v);
    }
  const int axis = hi[1] - lo[1] > hi[0] - lo[0] ? cy : cx;
  for (size_t r = 0; r < t.rows.size(); ++r) pts.emplace_back(t.number(r, axis), t.number(r, cp));
  std::sort(pts.begin(), pts.end());
  return pts;
}

double json_number(const nlohmann::json& j, std::initializer_list<const char*> path) {
  const nlohmann::json* node = &j;
  for (const char* key : path) {
    if (!node->is_object() || !node->contains(key)) return std::nan("");
    node = &(*node)[key];
  }
  return node->is_number() ? node->get<double>() : std::nan("");
}

std::string cell(double v) {
  if (!std::isfinite(v)) return "";
  std::ostringstream os;
  os << std::setprecision(8) << v;
  return os.str();
}

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

struct CompareRow {
  bool done = false;
  int level = 0;
  std::string method;
  double mesh_scale = 1.0;
  int exit_code = -1;
  std::string status = "not run";
  double dofs = std::nan(""), iterations = std::nan(""), newton = std::nan("");
  double t_mesh = std::nan(""), t_assemble = std::nan(""), t_solve = std::nan(""),
         t_total = std::nan(""), wall = std::nan("");
  double p_max = std::nan(""), length = std::nan(""), force = std::nan(""),
         penetration = std::nan("");
  double err_p0 = std::nan(""), err_b = std::nan(""), err_profile = std::nan(""),
         zz = std::nan("");
  std::vector<std::pair<double, double>> profile;
  bool converged() const { return status == "converged"; }
};

const char* kCompareHeader =
    "level,method,mesh_scale,dofs,status,exit_code,iterations,newton_iterations,time_mesh,"
    "time_assemble,time_solve,time_total,wall,p_max,contact_length,total_force,max_penetration,"
    "error_p_max,error_contact_length,error_profile_l2,zz_error\n";

std::string compare_csv(const std::vector<CompareRow>& rows) {
  std::ostringstream os;
  os << kCompareHeader;
  for (const auto& r : rows) {
    if (!r.done) continue;
    std::string status = r.status;
    std::replace(status.begin(), status.end(), ',', ';');
    std::replace(status.begin(), status.end(), '\n', ' ');
    os << r.level << ',' << r.method << ',' << cell(r.mesh_scale) << ',' << cell(r.dofs) << ",\""
       << status << "\"," << r.exit_code << ',' << cell(r.iterations) << ',' << cell(r.newton)
       << ',' << cell(r.t_mesh) << ',' << cell(r.t_assemble) << ',' << cell(r.t_solve) << ','
       << cell(r.t_total) << ',' << cell(r.wall) << ',' << cell(r.p_max) << ','
       << cell(r.length) << ',' << cell(r.force) << ',' << cell(r.penetration) << ','
       << cell(r.err_p0) << ',' << cell(r.err_b) << ',' << cell(r.err_profile) << ','
       << cell(r.zz) << '\n';
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
  os << "| level | method | DOFs | status | iterations | solve | total | p_max | contact length | "
        "total force | max penetration | p_max error | length error | profile L2 error |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    if (!r.done) continue;
    os << "| " << r.level << " | " << r.method << " | " << cell(r.dofs) << " | " << r.status
       << " | " << cell(r.iterations) << " | " << seconds(r.t_solve) << " | "
       << seconds(r.t_total) << " | " << cell(r.p_max) << " | " << cell(r.length) << " | "
       << cell(r.force) << " | " << cell(r.penetration) << " | " << percent(r.err_p0) << " | "
       << percent(r.err_b) << " | " << percent(r.err_profile) << " |\n";
  }
  if (!charts.empty()) os << "\n" << charts;
  return os.str();
}

std::string chart_commands_accuracy(const std::string& dir, const std::vector<CompareRow>& rows,
                                    const std::vector<std::string>& methods,
                                    const std::string& metric) {
  std::ostringstream data, plot;
  int block = 0;
  plot << "set title 'Accuracy against solve time (" << metric_name(metric)
       << "; one point per refinement level)'\nset xlabel 'solve time (s)'\nset ylabel '"
       << metric_name(metric) << "'\nset logscale xy\nset grid\nset key outside right\nplot ";
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
    plot << (block ? ", \\\n     " : "") << "'" << dir << "/accuracy.dat' index " << block
         << " using 1:2 with linespoints pt 7 lw 2 title '" << m << "' noenhanced";
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
  const auto p0 = scene.reference.find("p_max"), b = scene.reference.find("contact_length");
  const bool hertz = scene.reference_kind.rfind("hertz", 0) == 0 && p0 != scene.reference.end() &&
                     b != scene.reference.end();
  const std::string metric = hertz ? "profile" : p0 != scene.reference.end() ? "p_max" : "";

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
    r.done = true;
    r.exit_code = c.exit_code;
    r.wall = c.wall_seconds;
    if (c.has_summary) {
      const auto& s = c.summary;
      r.status = s.value("status", std::string("unknown"));
      r.dofs = json_number(s, {"mesh", "dofs"});
      r.iterations = json_number(s, {"contact", "iterations"});
      r.newton = json_number(s, {"newton_iterations"});
      r.t_mesh = json_number(s, {"time_s", "mesh"});
      r.t_assemble = json_number(s, {"time_s", "assemble"});
      r.t_solve = json_number(s, {"time_s", "solve"});
      r.t_total = json_number(s, {"time_s", "total"});
      r.p_max = json_number(s, {"contact", "p_max"});
      r.length = json_number(s, {"contact", "length"});
      r.force = json_number(s, {"contact", "total_force"});
      r.penetration = json_number(s, {"contact", "max_penetration"});
      r.err_p0 = json_number(s, {"reference", "relative_error", "p_max"});
      r.err_b = json_number(s, {"reference", "relative_error", "contact_length"});
      r.zz = json_number(s, {"error", "relative_error"});
      if (r.converged()) {
        r.profile = read_profile(cases[i].out_dir);
        if (hertz) r.err_profile = hertz_profile_error(r.profile, p0->second, b->second);
      }
    } else {
      r.status = "crashed (exit " + std::to_string(c.exit_code) + ", no summary.json)";
      crashed = true;
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
      plot << "set xrange [" << std::max(lo, -1.6 * b->second) << ":"
           << std::min(hi, 1.6 * b->second) << "]\nset samples 400\nset key top left\n";
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
      plot << (n ? ", \\\n     " : "") << "'" << path << "' using 1:2 with linespoints pt "
           << 4 + n << " ps 0.7 title '" << r.method << "' noenhanced";
      ++n;
    }
    if (hertz)
      plot << (n ? ", \\\n     " : "") << "(abs(x) < " << b->second << " ? " << p0->second
           << "*sqrt(1-(x/" << b->second << ")**2) : 0) with lines lw 2 lc rgb 'black' dt 2 "
           << "title 'Hertz'";
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
      plot << (n ? ", \\\n     " : "") << "'" << out << "/penetration.dat' index " << n
           << " using 1:2 with linespoints pt 7 lw 2 title '" << m << "' noenhanced";
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
