#include "app/studies/bench.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "app/report/gnuplot.hpp"
#include "app/studies/studies.hpp"
#include "constraints/constraint_strategy.hpp"
#include "core/assembler.hpp"
#include "core/errors.hpp"
#include "core/elasticity_kernels.hpp"
#include "core/stopwatch.hpp"
#include "core/structured_grid.hpp"
#include "core/writers.hpp"

namespace fs = std::filesystem;

namespace c2d::app {

const char* const kBenchCsvHeader =
    "family,scene,element,method,nominal,mesh_scale,dofs,status,exit_code,newton_iterations,"
    "contact_iterations,factorizations,time_mesh,time_assemble,time_symbolic,time_numeric,"
    "time_triangular,time_contact_other,time_detection,time_solve,time_recovery,time_output,"
    "time_total,wall,peak_rss_mb,accuracy_measure,accuracy,zz_error,contact_overhead\n";

namespace {

// Mesh scales that bring each scene to about 10k, 100k and 1M DOFs: DOFs go as base / scale²,
// with the base fitted to measured ladders (the refinement zones scale less than the rest, so
// the base is below the DOFs at scale 1: cantilever T3 1,004 and T6 3,760 DOFs at scale 1,
// 773,776 and 829,482 at 1 / sqrt(1e6 / base) with the scale-1 base). The DOFs each run
// measures are what the tables report.
struct Family {
  const char* family;
  const char* scene;
  const char* element;
  double base_dofs;
};
constexpr Family kFamilies[] = {
    {"elasticity", "cantilever.toml", "T3", 780},     {"elasticity", "cantilever.toml", "T6", 3120},
    {"hertz_rigid", "hertz_rigid.toml", "T3", 5300},  {"hertz_rigid", "hertz_rigid.toml", "T6", 21500},
    {"hertz_block", "hertz_block.toml", "T3", 10000}, {"hertz_block", "hertz_block.toml", "T6", 39000},
};

double scale_for(double base_dofs, double dofs) { return std::sqrt(base_dofs / dofs); }

std::string rounded(double v) {
  std::ostringstream os;
  os << std::setprecision(3) << v;
  return os.str();
}

/// Every case: charts off (pictures for people, not a solver phase). The Hertz ladder narrows
/// the slave arc to the 4.4 mm (2.6 b) that can touch: the same physics with fewer rows.
std::vector<std::string> case_sets(const std::string& family) {
  std::vector<std::string> s{"output.charts=false"};
  if (family == "hertz_rigid" || family == "hertz_block")
    s.push_back("contact.slave.arc.from_deg=-90.5");
  return s;
}

}  // namespace

std::vector<BenchCase> bench_ladder(bool quick) {
  std::vector<BenchCase> cases;
  auto add = [&](const std::string& family, const std::string& scene, const std::string& element,
                 const std::string& method, double scale, const std::string& nominal) {
    BenchCase c{family, scene, element, method, scale, nominal, case_sets(family)};
    cases.push_back(c);
  };
  if (quick) {
    add("elasticity", "cantilever.toml", "T6", "", 1.0, "4k");
    add("elasticity", "cantilever.toml", "T6", "", 0.5, "15k");
    add("hertz_rigid", "hertz_rigid.toml", "T6", "lagrange", 4.0, "4k");
    add("hertz_rigid", "hertz_rigid.toml", "T6", "lagrange", 2.0, "9k");
    add("two_cantilevers", "two_cantilevers.toml", "T6", "lagrange", 2.0, "3k");
  } else {
    for (const auto& f : kFamilies)
      for (const auto& [dofs, nominal] :
           {std::pair{1e4, "10k"}, std::pair{1e5, "100k"}, std::pair{1e6, "1M"}}) {
        const std::string method = std::string(f.family) == "elasticity" ? "" : "lagrange";
        add(f.family, f.scene, f.element, method, scale_for(f.base_dofs, dofs), nominal);
      }
    add("two_cantilevers", "two_cantilevers.toml", "T6", "lagrange", scale_for(11380, 1e4), "10k");
    add("two_cantilevers", "two_cantilevers.toml", "T6", "lagrange", scale_for(11380, 1e5), "100k");
  }
  // Every method on the scenes meshed for time to accuracy, as shipped and (full ladder) refined
  // once more; the shipped lagrange runs are the time-to-accuracy figures.
  const std::vector<double> levels = quick ? std::vector<double>{1.0} : std::vector<double>{1.0, 0.5};
  for (const char* scene : {"hertz_rigid_fast.toml", "hertz_block_fast.toml"}) {
    for (double scale : levels)
      for (const auto& m : constraints::method_names()) {
        BenchCase c{"methods", scene, "T6", m, scale, scale == 1.0 ? "as shipped" : "refined",
                    {"output.charts=false", "output.fields=false"}};
        cases.push_back(c);
      }
  }
  return cases;
}

double loglog_slope(const std::vector<double>& x, const std::vector<double>& y) {
  std::vector<std::pair<double, double>> p;
  for (size_t i = 0; i < x.size() && i < y.size(); ++i)
    if (x[i] > 0 && y[i] > 0 && std::isfinite(x[i]) && std::isfinite(y[i]))
      p.emplace_back(std::log(x[i]), std::log(y[i]));
  if (p.size() < 2) return std::nan("");
  double mx = 0, my = 0;
  for (const auto& [a, b] : p) mx += a, my += b;
  mx /= p.size(), my /= p.size();
  double sxy = 0, sxx = 0;
  for (const auto& [a, b] : p) sxy += (a - mx) * (b - my), sxx += (a - mx) * (a - mx);
  return sxx > 0 ? sxy / sxx : std::nan("");
}

namespace {

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
  double excluding_mesh() const { return t_total - t_mesh; }
};

void read_row(BenchRow& r, const CaseOutcome& out) {
  if (!r.read(out)) return;
  const auto& s = out.summary;
  r.factorizations = json_number(s, {"solver", "numeric_factorizations"});
  r.t_recovery = json_number(s, {"time_s", "recovery"});
  r.t_output = json_number(s, {"time_s", "output"});
  r.t_symbolic = json_number(s, {"solver", "symbolic_s"});
  r.t_numeric = json_number(s, {"solver", "numeric_s"});
  r.t_triangular = json_number(s, {"solver", "triangular_solve_s"});
  r.t_detection = json_number(s, {"contact", "detection_seconds"});
  if (s.contains("contact") && s["contact"].is_object())
    r.t_contact_other = r.t_solve - r.t_symbolic - r.t_numeric - r.t_triangular;
  const double analyses = std::max(1.0, json_number(s, {"solver", "symbolic_analyses"}));
  const double numerics = std::max(1.0, r.factorizations);
  if (r.t_numeric > 0) r.one_linear_solve = r.t_symbolic / analyses + r.t_numeric / numerics;
  if (!r.converged()) return;
  // The accuracy each family's reference allows.
  for (const char* key : {"pressure_profile_l2", "tip_uy", "a_uy"}) {
    const double e = json_number(s, {"reference", "relative_error", key});
    if (std::isfinite(e)) {
      r.accuracy_measure = key;
      r.accuracy = std::abs(e);
      break;
    }
  }
}

std::string cell(double v) { return csv_number(v, 6); }

std::string csv_of(const std::vector<BenchRow>& rows) {
  std::ostringstream os;
  os << kBenchCsvHeader;
  for (const auto& r : rows) {
    if (!r.done) continue;
    os << r.c.family << ',' << r.c.scene << ',' << r.c.element << ',' << r.c.method << ','
       << r.c.nominal << ',' << cell(r.c.mesh_scale) << ',' << cell(r.dofs) << ','
       << r.csv_status() << ',' << r.exit_code << ',' << cell(r.newton) << ',' << cell(r.iterations) << ','
       << cell(r.factorizations) << ',' << cell(r.t_mesh) << ',' << cell(r.t_assemble) << ','
       << cell(r.t_symbolic) << ',' << cell(r.t_numeric) << ',' << cell(r.t_triangular) << ','
       << cell(r.t_contact_other) << ',' << cell(r.t_detection) << ',' << cell(r.t_solve) << ','
       << cell(r.t_recovery) << ',' << cell(r.t_output) << ',' << cell(r.t_total) << ','
       << cell(r.wall) << ',' << cell(r.peak_rss_mb) << ',' << r.accuracy_measure << ','
       << cell(r.accuracy) << ',' << cell(r.zz) << ',' << cell(r.overhead) << '\n';
  }
  return os.str();
}

/// Contact overhead: the whole contact solve over one linear solve (symbolic analysis plus one
/// numeric factorisation) of the same mesh, taken from the lagrange run of the same scene,
/// element and scale (its one factorisation is of K_ρ, K's pattern plus a few rows), else from
/// the run itself.
void fill_overheads(std::vector<BenchRow>& rows) {
  for (auto& r : rows) {
    if (!r.converged() || !std::isfinite(r.t_contact_other)) continue;
    double one = r.one_linear_solve;
    for (const auto& l : rows)
      if (l.c.method == "lagrange" && l.c.scene == r.c.scene && l.c.element == r.c.element &&
          l.c.mesh_scale == r.c.mesh_scale && std::isfinite(l.one_linear_solve))
        one = l.one_linear_solve;
    if (one > 0) r.overhead = r.t_solve / one;
  }
}

/// In-process refill assembly throughput on structured grids, one thread and all threads.
struct Throughput {
  double t3_serial = NAN, t6_serial = NAN, t3_parallel = NAN, t6_parallel = NAN;
  int threads = 1;
};

Throughput measure_assembly(bool quick) {
  Throughput t;
  t.threads = omp_get_max_threads();
  for (int order : {1, 2}) {
    const core::StructuredGrid g = core::make_structured_grid(quick ? 120 / order : 300 / order, order);
    core::Assembler a(g.mesh, g.dofs);
    auto ke_of = [&](int e, LocalMatrix& ke) {
      ke = core::element_stiffness(g.mesh.element_coords(e), g.material);
    };
    for (int threads : {1, t.threads}) {
      a.set_threads(threads);
      double best = 1e300;
      for (int rep = 0; rep < 5; ++rep) {
        core::Stopwatch clock;
        a.assemble(ke_of, nullptr, nullptr);
        best = std::min(best, clock.elapsed());
      }
      const double rate = g.mesh.num_elements() / best;
      (order == 1 ? (threads == 1 ? t.t3_serial : t.t3_parallel)
                  : (threads == 1 ? t.t6_serial : t.t6_parallel)) = rate;
    }
  }
  return t;
}

std::string machine_line() {
  std::string cpu = "unknown CPU";
  std::ifstream info("/proc/cpuinfo");
  for (std::string line; std::getline(info, line);)
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  double mem_gb = NAN;
  std::ifstream mem("/proc/meminfo");
  for (std::string key; mem >> key;) {
    double kb = 0;
    mem >> kb;
    if (key == "MemTotal:") {
      mem_gb = kb / 1048576.0;
      break;
    }
    mem.ignore(256, '\n');
  }
  std::ostringstream os;
  os << cpu << ", " << omp_get_num_procs() << " cores, " << std::setprecision(3) << mem_gb
     << " GiB; OpenMP threads " << omp_get_max_threads();
  return os.str();
}

std::string fmt_s(double v) { return std::isfinite(v) ? rounded(v) + " s" : "–"; }
std::string fmt_pct(double v) { return std::isfinite(v) ? rounded(100 * v) + " %" : "–"; }

const BenchRow* find_row(const std::vector<BenchRow>& rows, const std::string& family,
                         const std::string& element, const std::string& nominal,
                         const std::string& scene = "", const std::string& method = "") {
  for (const auto& r : rows)
    if (r.done && r.c.family == family && (element.empty() || r.c.element == element) &&
        r.c.nominal == nominal && (scene.empty() || r.c.scene == scene) &&
        (method.empty() || r.c.method == method))
      return &r;
  return nullptr;
}

std::string verdict(bool measured, bool met) { return !measured ? "not run" : met ? "met" : "**not met**"; }

std::string targets_md(const std::vector<BenchRow>& rows, const Throughput& t, bool quick) {
  std::ostringstream md;
  md << "| target | required | measured | verdict |\n|---|---|---|---|\n";
  md << "| refill assembly, T3, per core | ≥ 2 M elements/s | " << rounded(t.t3_serial / 1e6)
     << " M/s (" << t.threads << " threads: " << rounded(t.t3_parallel / 1e6) << " M/s) | "
     << verdict(true, t.t3_serial >= 2e6) << " |\n";
  md << "| refill assembly, T6, per core | ≥ 0.5 M elements/s | " << rounded(t.t6_serial / 1e6)
     << " M/s (" << t.threads << " threads: " << rounded(t.t6_parallel / 1e6) << " M/s) | "
     << verdict(true, t.t6_serial >= 0.5e6) << " |\n";
  for (const char* el : {"T3", "T6"}) {
    const BenchRow* r = find_row(rows, "elasticity", el, "1M");
    const bool ok = r && r->converged();
    const double solve = ok ? r->t_assemble + r->t_solve : NAN;
    md << "| 1M-DOF linear elastic solve, " << el << " (assemble + factorise + solve) | < 10 s | "
       << (ok ? fmt_s(solve) + " at " + cell(r->dofs) + " DOFs; mesh excluded with recovery "
                                                          "and output: " +
                    fmt_s(r->excluding_mesh())
              : std::string(quick ? "–" : "failed"))
       << " | " << verdict(ok, solve < 10) << " |\n";
    md << "| 1M-DOF linear elastic run, " << el << ", peak memory | < 4 GB | "
       << (ok ? rounded(r->peak_rss_mb / 1024) + " GB" : "–") << " | " << verdict(ok, ok && r->peak_rss_mb < 4096)
       << " |\n";
  }
  // Contact overhead: every Hertz ladder run and every method of the panel.
  double worst_exact = 0;
  std::ostringstream list;
  bool any = false;
  for (const auto& r : rows)
    if (std::isfinite(r.overhead) && r.c.family != "two_cantilevers") {
      any = true;
      if (r.c.method == "lagrange" || r.c.method == "ssn") worst_exact = std::max(worst_exact, r.overhead);
    }
  for (const auto& r : rows)
    if (std::isfinite(r.overhead) && r.c.family != "methods" && r.c.family != "two_cantilevers")
      list << r.c.family << " " << r.c.element << " " << r.c.nominal << ": " << rounded(r.overhead) << "; ";
  md << "| contact overhead, lagrange and ssn (contact solve / one linear solve) | ≤ 2 | worst "
     << rounded(worst_exact) << " (ladder, lagrange: " << list.str()
     << "every method: table below) | " << verdict(any, worst_exact <= 2) << " |\n";
  for (const auto& [scene, limit, goal] :
       {std::tuple{"hertz_rigid_fast.toml", 0.1, 0.005}, std::tuple{"hertz_block_fast.toml", 1.0, 0.01}}) {
    const BenchRow* r = find_row(rows, "methods", "T6", "as shipped", scene, "lagrange");
    const bool ok = r && r->converged();
    md << "| Hertz " << (std::string(scene).find("rigid") != std::string::npos ? "rigid flat" : "elastic block")
       << ", time to accuracy (" << scene << ", lagrange) | ≤ " << rounded(100 * goal) << " % in < "
       << limit << " s | "
       << (ok ? fmt_pct(r->accuracy) + " in " + fmt_s(r->t_total) + " scene to summary (process " +
                    fmt_s(r->wall) + " with start-up), " + cell(r->dofs) + " DOFs"
              : std::string("–"))
       << " | " << verdict(ok, ok && r->accuracy <= goal && r->t_total < limit) << " |\n";
  }
  double worst_detection = NAN;
  for (const auto& r : rows)
    if (r.c.nominal == "1M" && r.converged() && std::isfinite(r.t_detection) && r.t_solve > 0)
      worst_detection = std::max(std::isfinite(worst_detection) ? worst_detection : 0.0,
                                 r.t_detection / r.t_solve);
  md << "| contact detection at 1M DOFs | ≤ 5 % of the solve | "
     << (std::isfinite(worst_detection) ? "worst " + fmt_pct(worst_detection) : std::string("–"))
     << " | " << verdict(std::isfinite(worst_detection), worst_detection <= 0.05) << " |\n";
  return md.str();
}

std::string ladder_md(const std::vector<BenchRow>& rows) {
  std::ostringstream md;
  md << "| family | element | rung | DOFs | status | mesh | assemble | symbolic | numeric | "
        "triangular | contact other | recovery | output | total | process | peak RSS | "
        "accuracy | overhead |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    if (!r.done || r.c.family == "methods") continue;
    md << "| " << r.c.family << " | " << r.c.element << " | " << r.c.nominal << " | "
       << cell(r.dofs) << " | " << r.status << " | " << fmt_s(r.t_mesh) << " | "
       << fmt_s(r.t_assemble) << " | " << fmt_s(r.t_symbolic) << " | " << fmt_s(r.t_numeric)
       << " | " << fmt_s(r.t_triangular) << " | " << fmt_s(r.t_contact_other) << " | "
       << fmt_s(r.t_recovery) << " | " << fmt_s(r.t_output) << " | " << fmt_s(r.t_total) << " | "
       << fmt_s(r.wall) << " | " << rounded(r.peak_rss_mb) << " MB | "
       << (r.accuracy_measure.empty() ? "–" : r.accuracy_measure + " " + fmt_pct(r.accuracy))
       << " | " << (std::isfinite(r.overhead) ? rounded(r.overhead) : "–") << " |\n";
  }
  return md.str();
}

std::string methods_md(const std::vector<BenchRow>& rows) {
  std::ostringstream md;
  md << "| scene | mesh | method | DOFs | status | iterations | factorisations | solve | "
        "scene to summary | overhead | profile error |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    if (!r.done || r.c.family != "methods") continue;
    md << "| " << r.c.scene << " | " << r.c.nominal << " | " << r.c.method << " | " << cell(r.dofs)
       << " | " << r.status << " | " << cell(r.iterations) << " | " << cell(r.factorizations)
       << " | " << fmt_s(r.t_solve) << " | " << fmt_s(r.t_total) << " | "
       << (std::isfinite(r.overhead) ? rounded(r.overhead) : "–") << " | " << fmt_pct(r.accuracy)
       << " |\n";
  }
  return md.str();
}

/// Time against DOFs, log-log: left, the whole run without meshing per family; right, the
/// phases of the linear elastic T6 ladder. Each line's title carries its fitted slope.
std::string chart_time(const std::string& out, const std::vector<BenchRow>& rows,
                       std::string& slopes_md) {
  std::ostringstream data, left, right;
  int block = 0;
  std::ostringstream slopes;
  slopes << "| series | fitted slope (log time / log DOFs) |\n|---|---|\n";
  auto series = [&](std::ostringstream& plot, const std::string& title,
                    const std::vector<std::pair<double, double>>& pts) {
    if (pts.size() < 2) return;
    std::vector<double> x, y;
    for (const auto& [a, b] : pts) x.push_back(a), y.push_back(b), data << a << ' ' << b << '\n';
    data << "\n\n";
    const double slope = loglog_slope(x, y);
    slopes << "| " << title << " | " << rounded(slope) << " |\n";
    plot << (plot.tellp() > 0 ? ", \\\n     " : "plot ") << gp_file(out + "/time_vs_dofs.dat")
         << " index " << block++ << " using 1:2 with linespoints lw 2 pt 7 title "
         << gp_text(title + " (slope " + rounded(slope) + ")") << " noenhanced";
  };
  std::map<std::string, std::vector<std::pair<double, double>>> families;
  for (const auto& r : rows)
    if (r.converged() && r.c.family != "methods" && std::isfinite(r.dofs))
      families[r.c.family + " " + r.c.element].emplace_back(r.dofs, r.excluding_mesh());
  for (const auto& [name, pts] : families) series(left, name + ", run without mesh", pts);
  std::map<std::string, std::vector<std::pair<double, double>>> phases;
  for (const auto& r : rows)
    if (r.converged() && r.c.family == "elasticity" && r.c.element == "T6") {
      phases["mesh"].emplace_back(r.dofs, r.t_mesh);
      phases["assemble"].emplace_back(r.dofs, r.t_assemble);
      phases["factorise (symbolic + numeric)"].emplace_back(r.dofs, r.t_symbolic + r.t_numeric);
      phases["triangular solve"].emplace_back(r.dofs, r.t_triangular);
      phases["recovery (L2 smoothing, ZZ)"].emplace_back(r.dofs, r.t_recovery);
      phases["output"].emplace_back(r.dofs, r.t_output);
    }
  for (const auto& [name, pts] : phases) series(right, "elasticity T6: " + name, pts);
  slopes_md = slopes.str();
  if (block == 0) return "";
  core::write_file_atomic(out + "/time_vs_dofs.dat", data.str());
  std::ostringstream plot;
  plot << "set multiplot layout 1," << ((left.tellp() > 0) + (right.tellp() > 0))
       << "\nset logscale xy\nset grid\nset xlabel 'DOFs'\n"
       << "set ylabel 'seconds'\nset key top left font ',9'\nset format x '10^{%L}'\n";
  if (left.tellp() > 0) plot << "set title 'Whole run without meshing, per family'\n" << left.str() << "\n";
  if (right.tellp() > 0) plot << "set title 'Phases, linear elasticity T6'\n" << right.str() << "\n";
  plot << "unset multiplot\n";
  const std::string err = plot_png_and_svg(out, "time_vs_dofs", plot.str());
  fs::remove(out + "/time_vs_dofs.dat");
  return err;
}

/// Accuracy against time: every method on the time-to-accuracy scenes (one panel per scene,
/// one line per method through its meshes), with the lagrange Hertz ladders for scale.
std::string chart_accuracy(const std::string& out, const std::vector<BenchRow>& rows) {
  std::ostringstream data, panels;
  int block = 0, count = 0;
  for (const auto& [scene, ladder] : {std::pair{"hertz_rigid_fast.toml", "hertz_rigid"},
                                      std::pair{"hertz_block_fast.toml", "hertz_block"}}) {
    std::ostringstream lines;
    auto line = [&](const std::string& title, const std::vector<std::pair<double, double>>& pts) {
      if (pts.empty()) return;
      for (const auto& [a, b] : pts) data << a << ' ' << b << '\n';
      data << "\n\n";
      lines << (lines.tellp() > 0 ? ", \\\n     " : "plot ") << gp_file(out + "/accuracy_vs_time.dat")
            << " index " << block++ << " using 1:2 with linespoints lw 2 pt 7 title "
            << gp_text(title) << " noenhanced";
    };
    for (const auto& m : constraints::method_names()) {
      std::vector<std::pair<double, double>> pts;
      for (const auto& r : rows)
        if (r.c.family == "methods" && r.c.scene == scene && r.c.method == m && r.converged() &&
            r.accuracy > 0)
          pts.emplace_back(r.t_total, r.accuracy);
      std::sort(pts.begin(), pts.end());
      line(m, pts);
    }
    for (const char* el : {"T3", "T6"}) {
      std::vector<std::pair<double, double>> pts;
      for (const auto& r : rows)
        if (r.c.family == ladder && r.c.element == el && r.converged() && r.accuracy > 0)
          pts.emplace_back(r.t_total, r.accuracy);
      std::sort(pts.begin(), pts.end());
      line(std::string(ladder) + " ladder " + el + " (lagrange, point-graded mesh)", pts);
    }
    if (lines.tellp() > 0)
      panels << "set title " << gp_text(scene) << " noenhanced\n" << lines.str() << "\n", ++count;
  }
  if (count == 0) return "";
  std::ostringstream plot;
  plot << "set multiplot layout 1," << count << "\nset logscale xy\nset grid\n"
       << "set xlabel 'seconds, scene to summary'\n"
       << "set ylabel 'pressure profile error (relative L2)'\nset key top right font ',9'\n"
       << panels.str() << "unset multiplot\n";
  core::write_file_atomic(out + "/accuracy_vs_time.dat", data.str());
  const std::string err = plot_png_and_svg(out, "accuracy_vs_time", plot.str());
  fs::remove(out + "/accuracy_vs_time.dat");
  return err;
}

}  // namespace

int run_bench(const BenchOptions& o) {
  const std::string out = o.out.empty() ? "out/bench" : o.out;
  const std::string examples = o.examples;
  const std::vector<BenchCase> ladder = bench_ladder(o.quick);
  for (const auto& c : ladder)
    if (!fs::exists(examples + "/" + c.scene))
      throw InputError(examples + "/" + c.scene + ": bench scene not found (expected the bundled "
                       "examples folder; pass --examples DIR)");
  fs::create_directories(out);
  const core::Stopwatch clock;
  std::vector<BenchRow> rows(ladder.size());
  std::vector<StudyCase> cases;
  for (size_t i = 0; i < ladder.size(); ++i) {
    const BenchCase& c = ladder[i];
    rows[i].c = c;
    StudyCase s;
    char dir[160];
    std::snprintf(dir, sizeof dir, "%s/%02zu_%s_%s_%s_%s", out.c_str(), i, c.family.c_str(),
                  fs::path(c.scene).stem().c_str(), c.element.c_str(),
                  c.method.empty() ? "linear" : c.method.c_str());
    s.out_dir = dir;
    s.args = {examples + "/" + c.scene, "--quiet", "--out", s.out_dir,
              "--set", "analysis.element=" + c.element,
              "--set", "analysis.mesh_scale=" + cell(c.mesh_scale)};
    if (!c.method.empty()) s.args.insert(s.args.end(), {"--method", c.method});
    for (const auto& set : c.sets) s.args.insert(s.args.end(), {"--set", set});
    cases.push_back(s);
  }
  // One case at a time: timings of concurrent runs would measure each other.
  size_t finished = 0;
  run_cases(cases, 1, [&](size_t i, const CaseOutcome& outcome) {
    read_row(rows[i], outcome);
    ++finished;
    if (!o.quiet) {
      const BenchRow& r = rows[i];
      std::printf("bench %2zu/%zu  %-15s %-22s %s %-16s %9s DOFs  %8.3f s  %7.0f MB  %s\n",
                  finished, rows.size(), r.c.family.c_str(), r.c.scene.c_str(), r.c.element.c_str(),
                  r.c.method.empty() ? "-" : r.c.method.c_str(), cell(r.dofs).c_str(), r.wall,
                  r.peak_rss_mb, r.status.c_str());
      std::fflush(stdout);
    }
    fill_overheads(rows);
    core::write_file_atomic(out + "/bench.csv", csv_of(rows));  // complete after the last case
  });
  if (!o.quiet) std::printf("bench: assembly throughput (structured grids, in process)\n");
  const Throughput t = measure_assembly(o.quick);

  std::string slopes;
  std::string chart_error = chart_time(out, rows, slopes);
  if (chart_error.empty()) chart_error = chart_accuracy(out, rows);
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  std::ostringstream md;
  md << "# contact2d bench" << (o.quick ? " --quick" : "") << "\n\n"
     << date << "; " << machine_line() << "; " << rows.size() << " runs in "
     << rounded(clock.elapsed()) << " s.\n\n"
     << "Every run is a separate `contact2d run` process with charts off (the time-to-accuracy "
        "runs also without VTU/nodes.csv); phase times come from its summary.json, peak memory "
        "from the process (wait4), \"process\" is the wall time including start-up (loading "
        "gmsh's 90 shared libraries costs about 0.15 s). Accuracy: the pressure profile's "
        "relative L2 error over [0, 1.5 b] for Hertz, the tip deflection against Timoshenko "
        "beam theory for the cantilever (the converged 2D value is 0.13 % below it), the "
        "upper tip against the seed for the two cantilevers.\n\n"
     << "## Targets\n\n" << targets_md(rows, t, o.quick) << "\n"
     << "## Ladder\n\n" << ladder_md(rows) << "\n"
     << "## Every method on the time-to-accuracy scenes\n\n"
     << "Overhead = contact solve / (symbolic analysis + one numeric factorisation) of the "
        "same mesh.\n\n"
     << methods_md(rows) << "\n"
     << "## Cost against size\n\n" << slopes << "\n"
     << (chart_error.empty() ? "![time against DOFs](time_vs_dofs.png)\n\n"
                               "![accuracy against time](accuracy_vs_time.png)\n"
                             : "Charts not written: " + chart_error + "\n");
  core::write_file_atomic(out + "/bench.md", md.str());
  bool crashed = false;
  for (const auto& r : rows) crashed = crashed || r.status.rfind("crashed", 0) == 0;
  if (!o.quiet) {
    std::cout << "\n" << targets_md(rows, t, o.quick) << "\nwrote " << out
              << "/bench.csv, bench.md, time_vs_dofs and accuracy_vs_time (.png/.svg)\n";
    if (!chart_error.empty()) std::cout << "warning    chart not written: " << chart_error << "\n";
  }
  return crashed || !chart_error.empty() ? 1 : 0;
}

}  // namespace c2d::app
