#include "app/studies/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "app/studies/job_list.hpp"
#include "app/studies/study_metric.hpp"
#include "app/studies/sweep_report.hpp"
#include "constraints/contact_scene.hpp"
#include "constraints/method_registry.hpp"
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

namespace {

std::string cell(double v) { return csv_number(v); }

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

/// Whether the swept key is a regularisation's parameter (penalty stiffness or factor,
/// augmentation factor): then the exact method on the same mesh shows the error the
/// discretisation alone leaves, which no value of the key can remove.
bool has_baseline(const std::string& key, const std::string& method) {
  if (!method.empty() && constraints::is_exact_method(method)) return false;
  return key.find("penalty") != std::string::npos || key.find("auglag") != std::string::npos;
}

/// Validates the options against the scene (once, with the first value) and lays out a case per
/// value, and the baseline's case after them.
SweepStudy plan_sweep(const SweepOptions& o) {
  const SweptKey k = swept_key(o.sets);
  const std::vector<double> values = parse_range(k.spec, "--set " + k.key);
  std::vector<std::string> first = k.fixed;
  first.push_back(k.key + "=" + cell(values.front()));
  const core::Scene scene = core::load_scene(o.scene, first);
  if (o.jobs < 1)
    throw InputError("--jobs: expected an integer >= 1, found " + std::to_string(o.jobs));
  SweepStudy s;
  s.scene = o.scene;
  s.key = k.key;
  s.accuracy = o.accuracy;
  // A sweep is judged by p_max unless --metric says otherwise (against the reference when the
  // scene has one, else against the baseline).
  s.metric = choose_metric(scene, o.metric.empty() ? "p_max" : o.metric);
  if (o.metric.empty()) s.metric.why = "sweep's default";
  s.units = scene.units;
  s.out = study_out(o, "sweep");
  s.timing = timing_note(o.jobs);
  s.case_timeout_s = o.case_timeout_s;
  s.slurm = o.slurm;
  s.cases = sweep_cases(o, k, values);
  s.rows.resize(values.size());
  for (size_t i = 0; i < values.size(); ++i) s.rows[i].value = values[i];
  const std::string method =
      o.method.empty() ? constraints::parse_contact_scene(scene).options.method : o.method;
  if (has_baseline(k.key, method)) {
    s.baseline_method = kBaselineMethod;
    StudyCase c;
    c.folder = "baseline";
    c.args = {fs::absolute(o.scene).lexically_normal().string(), "--method", kBaselineMethod};
    for (const auto& set : k.fixed) c.args.insert(c.args.end(), {"--set", set});
    s.cases.push_back(c);
  }
  return s;
}

/// study.json's options and case keys: what the report needs besides the case folders.
void write_sweep_files(const SweepStudy& s) {
  const nlohmann::json options = {{"scene", s.scene},
                                  {"key", s.key},
                                  {"accuracy", s.accuracy},
                                  {"units", s.units},
                                  {"metric", s.metric.to_json()}};
  std::vector<nlohmann::json> keys;
  for (const auto& r : s.rows) keys.push_back({{"value", r.value}});
  if (!s.baseline_method.empty()) keys.push_back({{"baseline", s.baseline_method}});
  write_study_files(s.out, "sweep", options, s.cases, keys, s.case_timeout_s, s.slurm);
}

SweepStudy sweep_from_manifest(const StudyManifest& m) {
  const ManifestNode options = m.options();
  SweepStudy s;
  s.scene = options["scene"].text();
  s.key = options["key"].text();
  if (options.has("units")) s.units = options["units"].text();
  s.accuracy = options["accuracy"].number();
  // Studies written before --metric were judged by p_max's reference error.
  s.metric = StudyMetric::from_json(
      options.has("metric") ? options["metric"].json() : nlohmann::json("p_max"), m.file);
  s.out = m.dir;
  s.timing = merged_timing_note();
  s.cases = m.cases;
  for (size_t i = 0; i < m.cases.size(); ++i) {
    const ManifestNode keys = m.case_keys(i);
    if (keys.has("baseline")) {
      if (i + 1 != m.cases.size())
        throw InputError(m.file + ": cases[" + std::to_string(i) +
                         "]: expected the baseline as the last case, found it before others");
      s.baseline_method = keys["baseline"].text();
    } else {
      s.rows.emplace_back().value = keys["value"].number();
    }
  }
  return s;
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
    SweepRow& r = s.row(i);
    read_sweep_row(s, r, c);
    ++finished;
    core::write_file_atomic(s.out + "/sweep.csv", sweep_csv(s));
    if (!o.quiet)
      std::cout << "[" << finished << "/" << s.cases.size() << "] "
                << (i < s.rows.size() ? s.key + " = " : std::string("baseline ")) << std::left
                << std::setw(12) << (i < s.rows.size() ? cell(r.value) : s.baseline_method)
                << std::right << r.status
                << (r.timed_out() ? " after " + seconds_text(r.wall) : std::string())
                << (std::isfinite(r.err_p0) ? ", p_max error " + percent_text(r.err_p0)
                                            : std::string())
                << (std::isfinite(r.penetration) ? ", penetration " + cell(r.penetration)
                                                 : std::string())
                << std::endl;
  });
  std::vector<size_t> skip = timed_out_rows(s.rows);
  if (s.baseline.timed_out()) skip.push_back(s.rows.size());
  retime_cases(s.cases, s.out, o.jobs, o.case_timeout_s, skip, o.quiet,
               [&](size_t i, const RunFigures& f) { take_times(s.row(i), f); });
  return report_sweep(s, {}, o.quiet);
}

int merge_sweep(const StudyManifest& m, bool quiet) {
  SweepStudy s = sweep_from_manifest(m);
  const std::vector<size_t> missing = read_finished_cases(
      s.cases, s.out, [&](size_t i, const CaseOutcome& c) { read_sweep_row(s, s.row(i), c); });
  return report_sweep(s, missing, quiet);
}

}  // namespace c2d::app
