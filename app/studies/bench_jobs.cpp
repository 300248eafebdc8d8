#include "app/studies/bench_jobs.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

#include "app/process.hpp"
#include "app/report/csv_table.hpp"
#include "app/studies/bench_report.hpp"
#include "app/studies/study.hpp"
#include "core/errors.hpp"

namespace c2d::app {

namespace fs = std::filesystem;

double JobsComparison::worst_difference() const {
  double worst = method_names.empty() ? NAN : 0.0;
  for (size_t i = 0; i < method_names.size(); ++i)
    worst = std::max(worst, std::abs(solve_jobs2[i] - solve_jobs1[i]) / solve_jobs1[i]);
  return worst;
}

namespace {

/// compare.csv's solve time per method, in the order of `names` (filled on the first read).
std::vector<double> solve_times(const std::string& csv_path, std::vector<std::string>& names) {
  const CsvTable t = read_csv(csv_path);
  const int method = t.column("method"), solve = t.column("time_solve");
  std::vector<double> times;
  if (names.empty())
    for (const auto& row : t.rows) names.push_back(row[method]);
  for (const auto& name : names) {
    double v = NAN;
    for (size_t r = 0; r < t.rows.size(); ++r)
      if (t.rows[r][method] == name) v = t.number(r, solve);
    times.push_back(v);
  }
  return times;
}

}  // namespace

JobsComparison compare_jobs(const std::string& examples, const std::string& out, bool quick,
                            double case_timeout_s) {
  JobsComparison c;
  if (quick) {
    c.error = "not run by --quick (on its scenes a solve lasts milliseconds, below the noise)";
    return c;
  }
  c.repeats = 7;
  const std::string exe = this_executable();
  std::vector<double> lo, hi;
  for (int rep = 0; rep < c.repeats && c.error.empty(); ++rep)
    for (int jobs : {1, 2}) {
      const std::string dir = out + "/jobs_" + std::to_string(jobs) + "_" + std::to_string(rep);
      fs::remove_all(dir);
      const std::vector<std::string> args{"compare",
                                          examples + "/" + c.scene,
                                          "--methods",
                                          c.methods,
                                          "--levels",
                                          "1",
                                          "--jobs",
                                          std::to_string(jobs),
                                          "--quiet",
                                          "--out",
                                          dir,
                                          "--case-timeout",
                                          csv_number(case_timeout_s)};
      const ProcessOutcome p = run_process(exe, args, out + "/jobs_compare.log");
      if (!p.started || p.exit_code != 0) {
        c.error = "compare --jobs " + std::to_string(jobs) + " ended with " +
                  (p.started ? "exit code " + std::to_string(p.exit_code) : p.error) +
                  " (see jobs_compare.log)";
        break;
      }
      try {
        const std::vector<double> t = solve_times(dir + "/compare.csv", c.method_names);
        auto& best = jobs == 1 ? c.solve_jobs1 : c.solve_jobs2;
        if (best.empty()) best.assign(t.size(), std::numeric_limits<double>::infinity());
        if (lo.empty()) lo.assign(t.size(), INFINITY), hi.assign(t.size(), 0.0);
        for (size_t i = 0; i < t.size(); ++i) {
          best[i] = std::min(best[i], t[i]);
          lo[i] = std::min(lo[i], t[i]);
          hi[i] = std::max(hi[i], t[i]);
        }
      } catch (const InputError& e) {
        c.error = e.what();
        break;
      }
      fs::remove_all(dir);  // the figures are in bench.md; the folders would only hold copies
    }
  if (!c.error.empty()) {
    c.method_names.clear();
    return c;
  }
  for (size_t i = 0; i < lo.size(); ++i) c.spread.push_back(hi[i] / lo[i]);
  return c;
}

std::string jobs_md(const JobsComparison& c) {
  std::ostringstream md;
  md << "`contact2d compare " << c.scene << " --methods " << c.methods
     << " --levels 1`, with `--jobs 1` and with `--jobs 2`, " << c.repeats
     << " time(s) each, interleaved; the fastest solve of each setting (with --jobs 2 the "
        "times come from compare's timing pass, each case alone). Spread: the slowest over the "
        "fastest of all "
     << 2 * c.repeats << " runs of a method, the machine's noise.\n\n";
  if (!c.error.empty()) return md.str() + "Not measured: " + c.error + "\n";
  md << "| method | solve, --jobs 1 | solve, --jobs 2 | difference | spread |\n|---|---|---|---|---|\n";
  for (size_t i = 0; i < c.method_names.size(); ++i)
    md << "| " << c.method_names[i] << " | " << rounded(c.solve_jobs1[i]) << " s | "
       << rounded(c.solve_jobs2[i]) << " s | "
       << rounded(100.0 * (c.solve_jobs2[i] - c.solve_jobs1[i]) / c.solve_jobs1[i]) << " % | "
       << rounded(c.spread[i]) << " |\n";
  return md.str();
}

}  // namespace c2d::app
