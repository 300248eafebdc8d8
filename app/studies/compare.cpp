#include "app/studies/compare.hpp"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>

#include "app/studies/compare_report.hpp"
#include "app/studies/job_list.hpp"
#include "constraints/contact_scene.hpp"
#include "constraints/method_registry.hpp"
#include "core/errors.hpp"
#include "core/scene.hpp"
#include "core/writers.hpp"

namespace fs = std::filesystem;

namespace c2d::app {

namespace {

std::string cell(double v) { return csv_number(v); }

/// --methods, checked against the known ones (all of them when empty).
std::vector<std::string> chosen_methods(const CompareOptions& o) {
  std::vector<std::string> methods = o.methods;
  if (methods.empty()) methods = constraints::method_names();
  for (const auto& m : methods)
    if (!constraints::find_method(m))
      throw InputError("--methods: expected a comma-separated list of " +
                       constraints::method_list(", ") + ", found '" + m + "'");
  return methods;
}

/// Validates the options against the scene and lays out one case per level and method, each
/// in levelK/METHOD of the study folder, the scene by its absolute path (the case may run from
/// any folder).
CompareStudy plan_compare(const CompareOptions& o) {
  const core::Scene scene = core::load_scene(o.scene, o.sets);
  if (constraints::parse_contact_scene(scene, "").empty() &&
      !(scene.explicit_model && !scene.explicit_model->gaps.empty()))
    throw InputError(o.scene + ": compare needs a scene with [[contact]] (found none)");
  CompareStudy s;
  s.scene = o.scene;
  s.methods = chosen_methods(o);
  s.levels = o.levels;
  if (o.levels < 1 || o.levels > 8)
    throw InputError("--levels: expected an integer from 1 to 8, found " +
                     std::to_string(o.levels));
  if (o.jobs < 1)
    throw InputError("--jobs: expected an integer >= 1, found " + std::to_string(o.jobs));
  s.out = study_out(o, "compare");
  s.timing = timing_note(o.jobs);
  s.case_timeout_s = o.case_timeout_s;
  s.slurm = o.slurm;
  s.hertz = hertz_reference(scene);
  s.units = scene.units;
  s.metric = choose_metric(scene, o.metric);
  const std::string scene_path = fs::absolute(o.scene).lexically_normal().string();
  for (int level = 0; level < o.levels; ++level) {
    const double scale = scene.analysis.mesh_scale / std::pow(2.0, level);
    for (const auto& m : s.methods) {
      StudyCase c;
      c.folder = "level" + std::to_string(level) + "/" + m;
      c.args = {scene_path, "--method", m};
      for (const auto& set : o.sets) c.args.insert(c.args.end(), {"--set", set});
      c.args.insert(c.args.end(), {"--set", "analysis.mesh_scale=" + cell(scale)});
      s.cases.push_back(c);
      CompareRow r;
      r.level = level;
      r.method = m;
      r.mesh_scale = scale;
      s.rows.push_back(r);
    }
  }
  return s;
}

/// study.json's options and case keys: what the report needs besides the case folders.
void write_compare_files(const CompareStudy& s) {
  nlohmann::json hertz;  // null without a Hertz reference
  if (s.hertz) hertz = {{"p0", s.hertz->p0}, {"b", s.hertz->b}};
  const nlohmann::json options = {{"scene", s.scene},
                                  {"methods", s.methods},
                                  {"levels", s.levels},
                                  {"metric", s.metric.to_json()},
                                  {"units", s.units},
                                  {"hertz", hertz}};
  std::vector<nlohmann::json> keys;
  for (const auto& r : s.rows)
    keys.push_back({{"level", r.level}, {"method", r.method}, {"mesh_scale", r.mesh_scale}});
  write_study_files(s.out, "compare", options, s.cases, keys, s.case_timeout_s, s.slurm);
}

CompareStudy compare_from_manifest(const StudyManifest& m) {
  const ManifestNode options = m.options();
  CompareStudy s;
  s.scene = options["scene"].text();
  if (options.has("units")) s.units = options["units"].text();
  s.methods = options["methods"].texts();
  s.levels = options["levels"].integer();
  s.metric = StudyMetric::from_json(options["metric"].json(), m.file);
  if (!options["hertz"].json().is_null())
    s.hertz = HertzReference{options["hertz"]["p0"].number(), options["hertz"]["b"].number()};
  s.out = m.dir;
  s.timing = merged_timing_note();
  s.cases = m.cases;
  for (size_t i = 0; i < m.cases.size(); ++i) {
    const ManifestNode keys = m.case_keys(i);
    CompareRow r;
    r.level = keys["level"].integer();
    r.method = keys["method"].text();
    r.mesh_scale = keys["mesh_scale"].number();
    s.rows.push_back(r);
  }
  return s;
}

}  // namespace

int run_compare(const CompareOptions& o) {
  CompareStudy s = plan_compare(o);
  if (o.job_list) refuse_existing_cases(s.out, s.cases);
  write_compare_files(s);
  if (o.job_list) {
    if (!o.quiet) std::cout << job_list_note(s.out, s.cases.size(), o.case_timeout_s);
    return 0;
  }
  if (!o.quiet)
    std::cout << "compare    " << s.methods.size() << " methods x " << o.levels
              << " levels = " << s.cases.size() << " runs, " << o.jobs << " at a time -> " << s.out
              << "\n"
              << "metric     " << (s.metric.empty() ? "none" : s.metric.key) << " ("
              << s.metric.why << ")\n";
  size_t finished = 0;
  run_cases(s.cases, s.out, o.jobs, o.case_timeout_s, [&](size_t i, const CaseOutcome& c) {
    CompareRow& r = s.rows[i];
    read_row(r, c, s.out + "/" + s.cases[i].folder, s);
    ++finished;
    core::write_file_atomic(s.out + "/compare.csv", compare_csv(s.rows));
    if (!o.quiet)
      std::cout << "[" << finished << "/" << s.cases.size() << "] level " << r.level << " "
                << std::left << std::setw(17) << r.method << std::right << r.status
                << (r.timed_out() ? " after " + seconds_text(r.wall)
                                  : ", " + cell(r.dofs) + " DOFs, solve " + seconds_text(r.t_solve))
                << (std::isfinite(r.err_profile) ? ", profile error " + percent_text(r.err_profile)
                                                 : std::string())
                << std::endl;
  });
  retime_cases(s.cases, s.out, o.jobs, o.case_timeout_s, timed_out_rows(s.rows), o.quiet,
               [&](size_t i, const RunFigures& f) { take_times(s.rows[i], f); });
  return report_compare(s, {}, o.quiet);
}

int merge_compare(const StudyManifest& m, bool quiet) {
  CompareStudy s = compare_from_manifest(m);
  const std::vector<size_t> missing =
      read_finished_cases(s.cases, s.out, [&](size_t i, const CaseOutcome& c) {
        read_row(s.rows[i], c, s.out + "/" + s.cases[i].folder, s);
      });
  return report_compare(s, missing, quiet);
}

}  // namespace c2d::app
