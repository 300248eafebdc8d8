#include "app/studies/bench.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "app/output_folder.hpp"
#include "app/report/html_report.hpp"
#include "app/studies/bench_report.hpp"
#include "app/studies/job_list.hpp"
#include "core/assembler.hpp"
#include "core/elasticity_kernels.hpp"
#include "core/errors.hpp"
#include "core/stopwatch.hpp"
#include "core/structured_grid.hpp"
#include "core/writers.hpp"

namespace fs = std::filesystem;

namespace c2d::app {

const char* const kBenchCsvHeader =
    "family,scene,element,method,nominal,mesh_scale,dofs,status,exit_code,newton_iterations,"
    "contact_iterations,factorizations,time_mesh,time_assemble,time_symbolic,time_numeric,"
    "time_triangular,time_contact_other,time_detection,time_solve,time_recovery,time_output,"
    "time_total,wall,peak_rss_mb,accuracy_measure,accuracy,zz_error,contact_overhead,steps,"
    "newton_per_step,factorizations_per_step\n";


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
  r.steps = json_number(s, {"steps"});
  r.newton_per_step = json_number(s, {"per_step", "newton_iterations"});
  r.factorizations_per_step = json_number(s, {"per_step", "factorizations"});
  if (s.contains("contact") && s["contact"].is_object())
    r.t_contact_other = r.t_solve - r.t_symbolic - r.t_numeric - r.t_triangular;
  const double analyses = std::max(1.0, json_number(s, {"solver", "symbolic_analyses"}));
  const double numerics = std::max(1.0, r.factorizations);
  if (r.t_numeric > 0) r.one_linear_solve = r.t_symbolic / analyses + r.t_numeric / numerics;
  if (!r.converged()) return;
  // The accuracy each family's reference allows.
  for (const char* key :
       {"pressure_profile_l2", "tip_uy", "a_uy", "stick_length", "tangential_force"}) {
    const double e = json_number(s, {"reference", "relative_error", key});
    if (std::isfinite(e)) {
      r.accuracy_measure = key;
      r.accuracy = std::abs(e);
      break;
    }
  }
}

std::string csv_of(const std::vector<BenchRow>& rows) {
  std::ostringstream os;
  os << kBenchCsvHeader;
  for (const auto& r : rows) {
    if (!r.done) continue;
    os << r.c.family << ',' << r.c.scene << ',' << r.c.element << ',' << r.c.method << ','
       << r.c.nominal << ',' << bench_cell(r.c.mesh_scale) << ',' << bench_cell(r.dofs) << ','
       << r.csv_status() << ',' << r.exit_code << ',' << bench_cell(r.newton) << ','
       << bench_cell(r.iterations) << ',' << bench_cell(r.factorizations) << ','
       << bench_cell(r.t_mesh) << ',' << bench_cell(r.t_assemble) << ',' << bench_cell(r.t_symbolic)
       << ',' << bench_cell(r.t_numeric) << ',' << bench_cell(r.t_triangular) << ','
       << bench_cell(r.t_contact_other) << ',' << bench_cell(r.t_detection) << ','
       << bench_cell(r.t_solve) << ',' << bench_cell(r.t_recovery) << ',' << bench_cell(r.t_output)
       << ',' << bench_cell(r.t_total) << ',' << bench_cell(r.wall) << ','
       << bench_cell(r.peak_rss_mb) << ',' << r.accuracy_measure << ',' << bench_cell(r.accuracy)
       << ',' << bench_cell(r.zz) << ',' << bench_cell(r.overhead) << ',' << bench_cell(r.steps)
       << ',' << bench_cell(r.newton_per_step) << ',' << bench_cell(r.factorizations_per_step)
       << '\n';
  }
  return os.str();
}

/// Contact overhead: the whole contact solve over one linear solve (symbolic analysis plus one
/// numeric factorisation) of the same mesh. lagrange and ssn factorise K_ρ (K's pattern plus a
/// few rows) once: their own run's factorisation, timed in the same process as the contact
/// solve. The other methods take the lagrange run's of the same scene, element and scale (one
/// denominator for the methods table), else their own.
void fill_overheads(std::vector<BenchRow>& rows) {
  for (auto& r : rows) {
    if (!r.converged() || !std::isfinite(r.t_contact_other)) continue;
    double one = r.one_linear_solve;
    const bool own = (r.c.method == "lagrange" || r.c.method == "ssn") && std::isfinite(one);
    for (const auto& l : rows)
      if (!own && l.c.method == "lagrange" && l.c.scene == r.c.scene &&
          l.c.element == r.c.element && l.c.mesh_scale == r.c.mesh_scale &&
          std::isfinite(l.one_linear_solve))
        one = l.one_linear_solve;
    if (one > 0) r.overhead = r.t_solve / one;
  }
}

Throughput measure_assembly(bool quick) {
  Throughput t;
  t.threads = omp_get_max_threads();
  for (int order : {1, 2}) {
    const core::StructuredGrid g =
        core::make_structured_grid(quick ? 120 / order : 300 / order, order);
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

/// One `contact2d run` per rung, in its own folder NN_family_scene_element_method of the study
/// folder, the scene by its absolute path.
std::vector<StudyCase> bench_cases(const std::vector<BenchCase>& ladder,
                                   const std::string& examples) {
  const std::string folder = fs::absolute(examples).lexically_normal().string();
  std::vector<StudyCase> cases;
  for (size_t i = 0; i < ladder.size(); ++i) {
    const BenchCase& c = ladder[i];
    StudyCase s;
    char dir[160];
    std::snprintf(dir, sizeof dir, "%02zu_%s_%s_%s_%s", i, c.family.c_str(),
                  fs::path(c.scene).stem().c_str(), c.element.c_str(),
                  c.method.empty() ? "linear" : c.method.c_str());
    s.folder = dir;
    s.args = {folder + "/" + c.scene, "--set", "analysis.element=" + c.element, "--set",
              "analysis.mesh_scale=" + bench_cell(c.mesh_scale)};
    if (!c.method.empty()) s.args.insert(s.args.end(), {"--method", c.method});
    for (const auto& set : c.sets) s.args.insert(s.args.end(), {"--set", set});
    cases.push_back(s);
  }
  return cases;
}

void print_row(size_t finished, const std::vector<BenchRow>& rows, const BenchRow& r) {
  std::printf("bench %2zu/%zu  %-15s %-22s %s %-16s %9s DOFs  %8.3f s  %7.0f MB  %s\n", finished,
              rows.size(), r.c.family.c_str(), r.c.scene.c_str(), r.c.element.c_str(),
              r.c.method.empty() ? "-" : r.c.method.c_str(), bench_cell(r.dofs).c_str(), r.wall,
              r.peak_rss_mb, r.status.c_str());
  std::fflush(stdout);
}

/// What the steps of a bench share: the ladder's kind, the study folder, how its times were
/// taken (and, merged, where), the cases and their rows (same order).
struct BenchStudy {
  bool quick = false;
  double case_timeout_s = 0;      ///< per run; 0: none
  SlurmSettings slurm;            ///< slurm.sh's #SBATCH lines (for the job list)
  std::string out, timing, runs;  ///< runs: "44 runs in 660 s" or what a merge knows
  std::vector<StudyCase> cases;
  std::vector<BenchRow> rows;
};

/// The contact rungs below 1M DOFs and every method's time-to-accuracy runs run kRepeats more
/// times, one at a time, and each row keeps its fastest run (least solve time; the case folder
/// holds the first run's outputs). Their solves last 10 ms to 1 s, where one run's noise moved
/// a 10k rung's overhead from 1.36 to 1.54, and a 19k method run's from 1.86 to 2.4.
void repeat_short_contact_rungs(BenchStudy& s, bool quiet) {
  constexpr int kRepeats = 2;
  std::vector<StudyCase> again;
  std::vector<size_t> row_of;
  for (size_t i = 0; i < s.rows.size(); ++i) {
    const BenchRow& r = s.rows[i];
    const bool short_contact =
        (r.c.family.rfind("hertz_", 0) == 0 && r.c.nominal != "1M") || r.c.family == "methods";
    if (!short_contact || !r.converged()) continue;
    for (int k = 1; k <= kRepeats; ++k) {
      again.push_back(s.cases[i]);
      again.back().folder = "repeat" + std::to_string(k) + "/" + s.cases[i].folder;
      row_of.push_back(i);
    }
  }
  if (!quiet && !again.empty())
    std::printf("bench: %zu short contact runs again, the fastest kept\n", again.size());
  run_cases(again, s.out, 1, s.case_timeout_s, [&](size_t j, const CaseOutcome& outcome) {
    BenchRow r;
    r.c = s.rows[row_of[j]].c;
    read_row(r, outcome);
    if (r.converged() && r.t_solve < s.rows[row_of[j]].t_solve) s.rows[row_of[j]] = r;
  });
  for (int k = 1; k <= kRepeats; ++k) fs::remove_all(s.out + "/repeat" + std::to_string(k));
}

/// Under bench.md's and bench.html's title: when and where, and how the figures were taken.
std::string bench_intro_md(const BenchStudy& s, const std::string& date) {
  return date + "; " + machine_line() + "; " + s.runs +
         ".\n\n"
         "Every run is a separate `contact2d run` process with charts off (the time-to-accuracy "
         "runs also without VTU/nodes.csv); phase times come from its summary.json, peak memory "
         "from the process (wait4), \"process\" is the wall time including start-up (loading "
         "gmsh's 90 shared libraries costs about 0.15 s). Accuracy: the pressure profile's "
         "relative L2 error over [0, 1.5 b] for Hertz, the tip deflection against Timoshenko "
         "beam theory for the cantilever (the converged 2D value is 0.13 % below it), the "
         "upper tip against the seed for the two cantilevers. " +
         s.timing + "\n\n";
}

std::string bench_title(const BenchStudy& s) {
  return std::string("contact2d bench") + (s.quick ? " --quick" : "");
}

/// What bench.md and bench.html share besides the intro: the targets, then the slopes.
struct BenchText {
  std::string date, targets, slopes, jobs, chart_error;
};

/// bench.md: when and where, how the figures were taken, the targets, the tables, the slopes.
std::string bench_md(const BenchStudy& s, const std::vector<size_t>& missing, const BenchText& b,
                     const std::vector<ReportChart>& charts) {
  std::ostringstream md;
  md << "# " << bench_title(s) << "\n\n"
     << bench_intro_md(s, b.date) << missing_cases_md(s.cases, missing)
     << timed_out_cases_md(s.cases, figures_of(s.rows)) << "## Targets\n\n"
     << b.targets << "\n"
     << "## Ladder\n\n"
     << ladder_md(s.rows) << "\n"
     << "## Every method on the time-to-accuracy scenes\n\n"
     << "Overhead = contact solve / (symbolic analysis + one numeric factorisation) of the "
        "same mesh: for lagrange and ssn their own factorisation of K_ρ (ordered with the contact "
        "surface last), timed in the same process; for the other methods the lagrange run's.\n\n"
     << methods_md(s.rows) << "\n"
     << "## Load-stepped contact\n\n"
     << "Newton iterations and factorisations per converged load step (summary.json's "
        "per_step; cutbacks' work included), and the numeric factorisation's time per "
        "factorisation.\n\n"
     << stepped_md(s.rows) << "\n"
     << "## Study times against --jobs\n\n"
     << b.jobs << "\n"
     << "## Cost against size\n\n"
     << b.slopes << "\n"
     << markdown_images(charts)
     << (b.chart_error.empty() ? "" : "Charts not written: " + b.chart_error + "\n");
  return md.str();
}

/// bench.html: bench.md's intro, its targets as the verdict, bench.csv's every column, charts.
HtmlReport bench_html(const BenchStudy& s, const std::vector<size_t>& missing, const BenchText& b,
                      const std::string& csv, const std::vector<ReportChart>& charts) {
  return {bench_title(s),
          b.date,
          bench_intro_md(s, b.date),
          b.targets,
          missing_cases_md(s.cases, missing) + timed_out_cases_md(s.cases, figures_of(s.rows)) +
              "## Study times against --jobs\n\n" + b.jobs + "\n## Cost against size\n\n" +
              b.slopes,
          "bench.csv",
          csv,
          charts,
          {}};
}

/// study.json's options and case keys: what the report needs besides the case folders.
void write_bench_files(const BenchStudy& s) {
  std::vector<nlohmann::json> keys;
  for (const auto& r : s.rows)
    keys.push_back({{"family", r.c.family},
                    {"scene", r.c.scene},
                    {"element", r.c.element},
                    {"method", r.c.method},
                    {"mesh_scale", r.c.mesh_scale},
                    {"nominal", r.c.nominal},
                    {"sets", r.c.sets}});
  write_study_files(s.out, "bench", {{"quick", s.quick}}, s.cases, keys, s.case_timeout_s,
                    s.slurm);
}

BenchStudy bench_from_manifest(const StudyManifest& m) {
  BenchStudy s;
  s.quick = m.options()["quick"].boolean();
  s.out = m.dir;
  s.timing = merged_timing_note();
  s.cases = m.cases;
  for (size_t i = 0; i < m.cases.size(); ++i) {
    const ManifestNode k = m.case_keys(i);
    BenchRow r;
    r.c = BenchCase{k["family"].text(), k["scene"].text(),        k["element"].text(),
                    k["method"].text(), k["mesh_scale"].number(), k["nominal"].text(),
                    k["sets"].texts()};
    s.rows.push_back(r);
  }
  return s;
}

/// The assembly throughput (measured here, now), bench.md and the charts from the finished
/// rows, listing the `missing` cases and those that timed out; the targets on the terminal
/// unless quiet. Returns 1 when a case crashed, timed out or is missing or a chart failed,
/// else 0.
int report_bench(BenchStudy& s, const std::vector<size_t>& missing, const JobsComparison& jobs,
                 bool quiet) {
  fill_overheads(s.rows);
  const std::string csv = csv_of(s.rows);
  core::write_file_atomic(s.out + "/bench.csv", csv);
  if (!quiet) std::printf("bench: assembly throughput (structured grids, in process)\n");
  const Throughput t = measure_assembly(s.quick);
  BenchText text{utc_now_text(), targets_md(s.rows, t, s.quick, jobs), phase_slopes_md(s.rows),
                 jobs_md(jobs), ""};
  std::vector<ReportChart> charts;
  std::string& chart_error = text.chart_error;
  chart_error = chart_time(s.out, s.rows, charts);
  if (chart_error.empty())
    chart_error = chart_accuracy(s.out, s.rows, charts);
  else
    charts.push_back({"accuracy_vs_time", "accuracy against time",
                      "not drawn after the failure of an earlier chart"});
  core::write_file_atomic(s.out + "/bench.md", bench_md(s, missing, text, charts));
  write_html_report(s.out, "bench.html", bench_html(s, missing, text, csv, charts));
  if (!quiet) {
    std::cout << "\n"
              << missing_cases_text(s.cases, missing)
              << timed_out_cases_text(s.cases, figures_of(s.rows)) << text.targets << "\nwrote "
              << s.out
              << "/bench.csv, bench.md, bench.html, time_vs_dofs and accuracy_vs_time "
                 "(.png/.svg)\n";
    if (!chart_error.empty()) std::cout << "warning    chart not written: " << chart_error << "\n";
  }
  return any_case_failed(figures_of(s.rows)) || !missing.empty() || !chart_error.empty() ? 1 : 0;
}

}  // namespace

int run_bench(const BenchOptions& o) {
  BenchStudy s;
  s.quick = o.quick;
  s.case_timeout_s = o.case_timeout_s;
  s.slurm = o.slurm;
  s.out = o.out.empty() ? "out/bench" : o.out;
  s.timing =
      "The Hertz rungs below 1M DOFs and the time-to-accuracy runs of every method ran "
      "three times, each row the fastest (least solve time). " +
      timing_note(1);
  const std::vector<BenchCase> ladder = bench_ladder(o.quick);
  for (const auto& c : ladder)
    if (!fs::exists(o.examples + "/" + c.scene))
      throw InputError(o.examples + "/" + c.scene +
                       ": bench scene not found (expected the bundled "
                       "examples folder; pass --examples DIR)");
  create_output_folder(s.out);
  s.cases = bench_cases(ladder, o.examples);
  s.rows.resize(ladder.size());
  for (size_t i = 0; i < ladder.size(); ++i) s.rows[i].c = ladder[i];
  if (o.job_list) refuse_existing_cases(s.out, s.cases);
  write_bench_files(s);
  if (o.job_list) {
    if (!o.quiet) std::cout << job_list_note(s.out, s.cases.size(), o.case_timeout_s);
    return 0;
  }
  const core::Stopwatch clock;
  // One case at a time: timings of concurrent runs would measure each other.
  size_t finished = 0;
  run_cases(s.cases, s.out, 1, s.case_timeout_s, [&](size_t i, const CaseOutcome& outcome) {
    read_row(s.rows[i], outcome);
    ++finished;
    if (!o.quiet) print_row(finished, s.rows, s.rows[i]);
    fill_overheads(s.rows);
    core::write_file_atomic(s.out + "/bench.csv", csv_of(s.rows));  // complete after the last
  });
  repeat_short_contact_rungs(s, o.quiet);
  s.runs = std::to_string(s.rows.size()) + " runs in " + rounded(clock.elapsed()) + " s";
  if (!o.quiet) std::printf("bench: compare with --jobs 1 and --jobs 2\n");
  const JobsComparison jobs = compare_jobs(fs::absolute(o.examples).lexically_normal().string(),
                                           s.out, o.quick, s.case_timeout_s);
  return report_bench(s, {}, jobs, o.quiet);
}

int merge_bench(const StudyManifest& m, bool quiet) {
  BenchStudy s = bench_from_manifest(m);
  const std::vector<size_t> missing = read_finished_cases(
      s.cases, s.out, [&](size_t i, const CaseOutcome& c) { read_row(s.rows[i], c); });
  s.runs = std::to_string(s.cases.size() - missing.size()) + " of " +
           std::to_string(s.cases.size()) +
           " runs merged from their folders (machine and assembly throughput: the merging "
           "machine's)";
  JobsComparison jobs;
  jobs.error = "a merge does not run compare (it measures one machine running cases side by side)";
  return report_bench(s, missing, jobs, quiet);
}

}  // namespace c2d::app
