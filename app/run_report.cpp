#include "app/run_report.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>

namespace c2d::app {

namespace {
// JSON has no NaN/inf: a non-finite number becomes null rather than an invalid file.
nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }
}  // namespace

nlohmann::json make_summary(const core::Scene& scene, const core::Model* model,
                            const core::Results* r, const std::string& status) {
  nlohmann::json j;
  j["status"] = status;
  j["scene"] = scene.path;
  j["title"] = scene.title;
  j["method"] = nullptr;
  j["steps"] = 1;
  j["newton_iterations"] = 0;
  j["contact"] = nullptr;
  if (model) {
    j["mesh"] = {{"nodes", model->mesh.num_nodes()},
                 {"elements", model->mesh.num_elements()},
                 {"dofs", model->mesh.num_dofs()},
                 {"free_dofs", model->dofs.num_free()},
                 {"element", model->mesh.order == 1 ? "T3" : "T6"}};
  }
  if (r) {
    j["time_s"] = {{"mesh", r->time.mesh},         {"assemble", r->time.assemble},
                   {"solve", r->time.solve},       {"recovery", r->time.recovery},
                   {"output", r->time.output},     {"total", r->time.total}};
    j["solver"] = {{"backend", r->solver.backend},
                   {"status", to_string(r->solver.status)},
                   {"relative_residual", number(r->solver.relative_residual)},
                   {"pivot_ratio", number(r->solver.pivot_ratio)},
                   {"symbolic_analyses", r->solver.symbolic_analyses},
                   {"numeric_factorizations", r->solver.numeric_factorizations},
                   {"message", r->solver.message}};
    j["error"] = {{"global_parameter", number(r->error.global_parameter)},
                  {"energy_norm", number(r->error.energy_norm)},
                  {"error_norm", number(r->error.error_norm)},
                  {"relative_error", number(r->error.relative_error)},
                  {"target", r->error.target}};
    nlohmann::json probes = nlohmann::json::object();
    for (const auto& [name, value] : r->probes) probes[name] = number(value);
    j["probes"] = probes;
  } else {
    j["probes"] = nlohmann::json::object();
  }
  if (!scene.reference_kind.empty()) {
    nlohmann::json ref = {{"kind", scene.reference_kind}};
    for (const auto& [k, v] : scene.reference) ref[k] = v;
    j["reference"] = ref;
  }
  return j;
}

std::string terminal_summary(const nlohmann::json& s, const std::string& out_dir) {
  std::ostringstream os;
  os << std::setprecision(6);
  os << "status     " << s["status"].get<std::string>() << '\n';
  if (s.contains("mesh"))
    os << "mesh       " << s["mesh"]["element"].get<std::string>() << ", "
       << s["mesh"]["nodes"] << " nodes, " << s["mesh"]["elements"] << " elements, "
       << s["mesh"]["dofs"] << " DOFs\n";
  if (s.contains("time_s"))
    os << "time       mesh " << s["time_s"]["mesh"].get<double>() << " s, assemble "
       << s["time_s"]["assemble"].get<double>() << " s, solve " << s["time_s"]["solve"].get<double>()
       << " s, total " << s["time_s"]["total"].get<double>() << " s\n";
  if (s["status"] == "converged" && s.contains("error") && !s["error"]["relative_error"].is_null())
    os << "ZZ error   " << 100.0 * s["error"]["relative_error"].get<double>()
       << " % (global parameter " << s["error"]["global_parameter"].get<double>() << " for target "
       << 100.0 * s["error"]["target"].get<double>() << " %)\n";
  for (const auto& [name, value] : s["probes"].items())
    os << "probe      " << name << " = " << (value.is_null() ? std::string("null") : value.dump())
       << '\n';
  os << "results    " << out_dir << "/ (summary.json, results.pvd, nodes.csv, deformed.png)\n";
  return os.str();
}

}  // namespace c2d::app
