#include "app/studies/calibrate.hpp"

#include <ceres/ceres.h>
#include <toml++/toml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/report/csv_table.hpp"
#include "app/run/solve_scene.hpp"
#include "core/errors.hpp"
#include "core/writers.hpp"

namespace c2d::app {

namespace {

struct Parameter {
  std::string key;     ///< as given
  std::string path;    ///< scene path of the value (without a component index)
  int component = -1;  ///< index into a vector value (load[0].total_force[1]), else -1
  std::vector<double> vector_value;  ///< the vector the component belongs to
  double initial = 0.0, lower = 0.0, upper = 0.0;
  bool log = true;
};

/// The scene value at a --set style path: on the first table the path leads to (see
/// core::tables_on_path); null when absent.
const toml::node* lookup(toml::table& root, const std::string& path) {
  std::vector<std::string> keys;
  std::stringstream ss(path);
  for (std::string k; std::getline(ss, k, '.');) keys.push_back(k);
  const std::string last = keys.back();
  keys.pop_back();
  const auto tables = core::tables_on_path(root, keys, false, "--fit " + path);
  return tables.empty() ? nullptr : tables.front()->get(last);
}

std::string format(double v) {
  std::ostringstream os;
  os << std::setprecision(12) << v;
  return os.str();
}

Parameter parse_parameter(const std::string& spec, const core::Scene& scene) {
  Parameter p;
  const auto eq = spec.find('=');
  p.key = spec.substr(0, eq);
  const std::string where = "--fit " + spec;
  static const std::map<std::string, std::string> alias{
      {"E", "material.E"}, {"nu", "material.nu"}, {"thickness", "material.thickness"}};
  p.path = alias.count(p.key) ? alias.at(p.key) : p.key;
  // A trailing [i] on a vector value: fit one component.
  if (const auto lb = p.path.rfind('['); lb != std::string::npos && p.path.back() == ']' &&
                                         p.path.find('.', lb) == std::string::npos) {
    const toml::node* whole = lookup(*scene.raw, p.path.substr(0, lb));
    if (whole && whole->is_array()) {
      p.component = std::atoi(p.path.substr(lb + 1).c_str());
      for (const auto& v : *whole->as_array())
        p.vector_value.push_back(v.value<double>().value_or(0.0));
      if (p.component < 0 || p.component >= static_cast<int>(p.vector_value.size()))
        throw InputError(where + ": component index out of range of the vector " +
                         p.path.substr(0, lb));
      p.path = p.path.substr(0, lb);
    }
  }
  std::optional<double> current;
  if (p.component >= 0) {
    current = p.vector_value[p.component];
  } else if (const toml::node* n = lookup(*scene.raw, p.path)) {
    current = n->value<double>();
  }
  if (eq != std::string::npos) {
    std::vector<std::string> parts;
    std::stringstream ss(spec.substr(eq + 1));
    for (std::string part; std::getline(ss, part, ':');) parts.push_back(part);
    if (parts.size() < 2 || parts.size() > 3)
      throw InputError(where + ": expected key=lower:upper[:log|lin], found '" +
                       spec.substr(eq + 1) + "'");
    char* end = nullptr;
    p.lower = std::strtod(parts[0].c_str(), &end);
    if (*end)
      throw InputError(where + ": expected a number as the lower bound, found '" + parts[0] + "'");
    p.upper = std::strtod(parts[1].c_str(), &end);
    if (*end)
      throw InputError(where + ": expected a number as the upper bound, found '" + parts[1] + "'");
    if (!(p.upper > p.lower)) throw InputError(where + ": expected lower < upper");
    p.log = p.lower > 0;
    if (parts.size() == 3) {
      if (parts[2] != "log" && parts[2] != "lin")
        throw InputError(where + ": expected 'log' or 'lin', found '" + parts[2] + "'");
      p.log = parts[2] == "log";
      if (p.log && !(p.lower > 0))
        throw InputError(where + ": a log scale needs a positive lower bound");
    }
    p.initial = current && *current >= p.lower && *current <= p.upper
                    ? *current
                    : (p.log ? std::sqrt(p.lower * p.upper) : 0.5 * (p.lower + p.upper));
  } else {
    if (!current)
      throw InputError(where + ": the scene has no number at '" + p.path + "'; give bounds as " +
                       p.key + "=lower:upper");
    p.initial = *current;
    if (p.initial > 0)
      p.lower = p.initial / 100, p.upper = p.initial * 100, p.log = true;
    else if (p.initial < 0)
      p.lower = p.initial * 100, p.upper = p.initial / 100, p.log = false;
    else
      throw InputError(where + ": the scene's value is 0; give bounds as " + p.key +
                       "=lower:upper");
  }
  return p;
}

/// The --set assignment of a parameter at value v.
std::string assignment(const Parameter& p, double v) {
  if (p.component < 0) return p.path + "=" + format(v);
  std::string text = p.path + "=[";
  for (size_t i = 0; i < p.vector_value.size(); ++i)
    text += (i ? ", " : "") + format(static_cast<int>(i) == p.component ? v : p.vector_value[i]);
  return text + "]";
}

struct Datum {
  std::string probe;
  double value = 0.0, weight = 1.0, scale = 1.0;
};

struct CalibrationModel {
  const CalibrateOptions& o;
  const std::vector<Parameter>& params;
  const std::vector<Datum>& data;
  int evaluations = 0;
  std::string last_failure;

  double value(int j, double theta) const { return params[j].log ? std::exp(theta) : theta; }

  /// Probe values at the parameters θ; false when the solve fails.
  bool probes(const double* theta, std::vector<double>& out) {
    ++evaluations;
    std::vector<std::string> sets = o.sets;
    for (size_t j = 0; j < params.size(); ++j)
      sets.push_back(assignment(params[j], value(static_cast<int>(j), theta[j])));
    const core::Scene scene = core::load_scene(o.scene, sets);
    const auto run = solve_scene(scene, o.method, {});
    if (run->results.status != SolveStatus::kConverged) {
      last_failure = run->results.message;
      return false;
    }
    out.clear();
    for (const auto& d : data) out.push_back(run->results.probes.at(d.probe));
    return true;
  }
};

struct CalibrationCost {
  CalibrationModel* model;
  bool operator()(double const* const* theta, double* residuals) const {
    std::vector<double> values;
    if (!model->probes(theta[0], values)) return false;
    for (size_t i = 0; i < values.size(); ++i) {
      const Datum& d = model->data[i];
      residuals[i] = d.weight * (values[i] - d.value) / d.scale;
    }
    return true;
  }
};

/// The measured probe values of --data, each naming one of the scene's [[probe]]s.
std::vector<Datum> read_measured(const CalibrateOptions& o, const core::Scene& scene) {
  const CsvTable table = read_csv(o.data);
  const int c_probe = table.column("probe"), c_value = table.column("value");
  const auto w_it = std::find(table.columns.begin(), table.columns.end(), "weight");
  std::vector<Datum> data;
  for (size_t r = 0; r < table.rows.size(); ++r) {
    Datum d;
    d.probe = table.rows[r][c_probe];
    const bool known = std::any_of(scene.probes.begin(), scene.probes.end(),
                                   [&](const core::ProbeSpec& p) { return p.name == d.probe; });
    if (!known) {
      std::string names;
      for (const auto& p : scene.probes) names += (names.empty() ? "" : ", ") + p.name;
      throw InputError(o.data + ":" + std::to_string(r + 2) +
                       ": expected the name of a [[probe]] of " + o.scene + " (" + names +
                       "), found '" + d.probe + "'");
    }
    d.value = table.number(r, c_value);
    if (!std::isfinite(d.value))
      throw InputError(o.data + ":" + std::to_string(r + 2) + ": expected a measured value");
    if (w_it != table.columns.end()) {
      const double w = table.number(r, static_cast<int>(w_it - table.columns.begin()));
      d.weight = std::isfinite(w) ? w : 1.0;
      if (!(d.weight >= 0))
        throw InputError(o.data + ":" + std::to_string(r + 2) + ": expected a weight >= 0");
    }
    d.scale = std::abs(d.value) > 0 ? std::abs(d.value) : 1.0;
    data.push_back(d);
  }
  if (data.empty()) throw InputError(o.data + ": expected at least one measured probe value");
  return data;
}

/// What a calibration found, for the files and the terminal.
struct Calibration {
  std::vector<double> theta;  ///< fitted, in the parameters' scales (log or lin)
  std::vector<double> sigma;  ///< standard deviations of the values (NaN when not estimated)
  std::string covariance_note;
  ceres::Solver::Summary summary;
  std::vector<double> initial_probes, fitted_probes;
  bool solved = false;  ///< the scene solves at the fitted parameters
  double seconds = 0.0;
  std::string status() const {
    return summary.IsSolutionUsable() && solved ? "converged" : "failed";
  }
};

/// Standard deviations: Ceres's covariance of θ, scaled by the residual variance.
void estimate_sigmas(ceres::Problem& problem, const CalibrationModel& model, Calibration& c) {
  const int n = static_cast<int>(model.params.size()), m = static_cast<int>(model.data.size());
  c.sigma.assign(n, std::nan(""));
  ceres::Covariance::Options co;
  co.algorithm_type = ceres::DENSE_SVD;
  co.null_space_rank = -1;
  ceres::Covariance covariance(co);
  double* theta = c.theta.data();
  std::vector<std::pair<const double*, const double*>> blocks{{theta, theta}};
  if (m <= n) {
    c.covariance_note = "not estimated: as many data as parameters leave no residual variance";
  } else if (c.summary.IsSolutionUsable() && covariance.Compute(blocks, &problem)) {
    std::vector<double> cov(n * n);
    covariance.GetCovarianceBlock(theta, theta, cov.data());
    const double variance = 2.0 * c.summary.final_cost / (m - n);
    c.covariance_note = "from the covariance, scaled by the residual variance";
    for (int j = 0; j < n; ++j) {
      const double s_theta = std::sqrt(std::max(0.0, cov[j * n + j] * variance));
      c.sigma[j] = model.params[j].log ? model.value(j, c.theta[j]) * s_theta : s_theta;
    }
  } else {
    c.covariance_note =
        "not available (rank-deficient Jacobian: the data do not determine every parameter)";
  }
}

/// Levenberg-Marquardt from the parameters' initial values within their bounds.
void fit_parameters(CalibrationModel& model, int max_iterations, Calibration& c) {
  const auto& params = model.params;
  const int n = static_cast<int>(params.size()), m = static_cast<int>(model.data.size());
  ceres::Problem problem;
  auto* cost = new ceres::DynamicNumericDiffCostFunction<CalibrationCost, ceres::CENTRAL>(
      new CalibrationCost{&model});
  cost->AddParameterBlock(n);
  cost->SetNumResiduals(m);
  double* theta = c.theta.data();
  problem.AddResidualBlock(cost, nullptr, theta);
  for (int j = 0; j < n; ++j) {
    problem.SetParameterLowerBound(theta, j,
                                   params[j].log ? std::log(params[j].lower) : params[j].lower);
    problem.SetParameterUpperBound(theta, j,
                                   params[j].log ? std::log(params[j].upper) : params[j].upper);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.logging_type = ceres::SILENT;
  options.max_num_iterations = max_iterations;
  options.function_tolerance = 1e-12;
  options.gradient_tolerance = 1e-14;
  options.parameter_tolerance = 1e-10;
  ceres::Solve(options, &problem, &c.summary);
  estimate_sigmas(problem, model, c);
}

nlohmann::json calibration_json(const CalibrateOptions& o, const CalibrationModel& model,
                                const Calibration& c) {
  const auto& params = model.params;
  const auto& data = model.data;
  nlohmann::json j;
  j["scene"] = o.scene;
  j["data"] = o.data;
  j["status"] = c.status();
  j["ceres"] = {{"termination", ceres::TerminationTypeToString(c.summary.termination_type)},
                {"message", c.summary.message},
                {"iterations", static_cast<int>(c.summary.iterations.size())},
                {"initial_cost", c.summary.initial_cost},
                {"final_cost", c.summary.final_cost},
                {"solves", model.evaluations},
                {"seconds", c.seconds}};
  j["covariance"] = c.covariance_note;
  for (size_t k = 0; k < params.size(); ++k)
    j["parameters"].push_back(
        {{"key", params[k].key},
         {"initial", params[k].initial},
         {"fitted", model.value(static_cast<int>(k), c.theta[k])},
         {"sigma", std::isfinite(c.sigma[k]) ? nlohmann::json(c.sigma[k]) : nlohmann::json()},
         {"lower", params[k].lower},
         {"upper", params[k].upper},
         {"scale", params[k].log ? "log" : "lin"}});
  for (size_t i = 0; i < data.size(); ++i)
    j["residuals"].push_back(
        {{"probe", data[i].probe},
         {"measured", data[i].value},
         {"weight", data[i].weight},
         {"initial", c.initial_probes[i]},
         {"fitted", c.solved ? nlohmann::json(c.fitted_probes[i]) : nlohmann::json()},
         {"relative_residual",
          c.solved ? nlohmann::json((c.fitted_probes[i] - data[i].value) / data[i].scale)
                   : nlohmann::json()}});
  return j;
}

std::string calibration_md(const CalibrateOptions& o, const CalibrationModel& model,
                           const Calibration& c) {
  const auto& params = model.params;
  const auto& data = model.data;
  std::ostringstream md;
  md << std::setprecision(6) << "# contact2d calibrate: " << o.scene << " against " << o.data
     << "\n\nCeres (Levenberg-Marquardt, central differences, one solve per evaluation): "
     << ceres::TerminationTypeToString(c.summary.termination_type) << " after "
     << c.summary.iterations.size() << " iterations and " << model.evaluations << " solves ("
     << c.seconds << " s); cost " << c.summary.initial_cost << " -> " << c.summary.final_cost
     << ". Standard deviations: " << c.covariance_note
     << ".\n\n| parameter | initial | fitted | ± σ | bounds |\n|---|---|---|---|---|\n";
  for (size_t k = 0; k < params.size(); ++k)
    md << "| " << params[k].key << " | " << params[k].initial << " | "
       << model.value(static_cast<int>(k), c.theta[k]) << " | "
       << (std::isfinite(c.sigma[k]) ? format(c.sigma[k]) : "–") << " | [" << params[k].lower
       << ", " << params[k].upper << "] " << (params[k].log ? "log" : "lin") << " |\n";
  md << "\n| probe | measured | initial | fitted | relative residual |\n|---|---|---|---|---|\n";
  for (size_t i = 0; i < data.size(); ++i)
    md << "| " << data[i].probe << " | " << data[i].value << " | " << c.initial_probes[i] << " | "
       << (c.solved ? format(c.fitted_probes[i]) : "–") << " | "
       << (c.solved ? format((c.fitted_probes[i] - data[i].value) / data[i].scale) : "–") << " |\n";
  return md.str();
}

void print_calibration(const std::string& out, const CalibrationModel& model,
                       const Calibration& c) {
  const auto& params = model.params;
  const auto& data = model.data;
  std::cout << "calibrate  " << c.status() << ": "
            << ceres::TerminationTypeToString(c.summary.termination_type) << ", "
            << c.summary.iterations.size() << " iterations, " << model.evaluations << " solves, "
            << std::setprecision(3) << c.seconds << " s\n";
  for (size_t k = 0; k < params.size(); ++k)
    std::cout << "parameter  " << params[k].key << " = " << std::setprecision(8)
              << model.value(static_cast<int>(k), c.theta[k])
              << (std::isfinite(c.sigma[k]) ? " ± " + format(c.sigma[k]) : "") << " (initial "
              << params[k].initial << ")\n";
  for (size_t i = 0; i < data.size(); ++i)
    std::cout << "probe      " << data[i].probe << ": measured " << data[i].value << ", fitted "
              << (c.solved ? format(c.fitted_probes[i]) : "–") << "\n";
  std::cout << "wrote " << out << "/calibrate.json, calibrate.md\n";
}

}  // namespace

int run_calibrate(const CalibrateOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  const core::Scene scene = core::load_scene(o.scene, o.sets);
  if (o.fits.empty()) throw InputError("calibrate: expected --fit key[,key...], found none");
  if (o.data.empty()) throw InputError("calibrate: expected --data measured.csv, found none");
  std::vector<Parameter> params;
  for (const auto& f : o.fits) params.push_back(parse_parameter(f, scene));
  const std::vector<Datum> data = read_measured(o, scene);
  const std::string out = study_out(o, "calibrate");

  CalibrationModel model{o, params, data, 0, {}};
  Calibration c;
  for (const auto& p : params) c.theta.push_back(p.log ? std::log(p.initial) : p.initial);
  if (!model.probes(c.theta.data(), c.initial_probes))
    throw InputError(o.scene + ": the scene does not solve at the initial parameters (" +
                     model.last_failure + ")");
  fit_parameters(model, o.max_iterations, c);
  c.solved = model.probes(c.theta.data(), c.fitted_probes);
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  core::write_file_atomic(out + "/calibrate.json", calibration_json(o, model, c).dump(2) + "\n");
  core::write_file_atomic(out + "/calibrate.md", calibration_md(o, model, c));
  if (!o.quiet) print_calibration(out, model, c);
  return c.status() == "converged" ? 0 : 1;
}

}  // namespace c2d::app
