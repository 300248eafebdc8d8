#include "app/report/run_report.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>

#include "app/report/hertz.hpp"
#include "app/report/pressure_profile.hpp"

namespace c2d::app {

namespace {
// JSON has no NaN/inf: a non-finite number becomes null rather than an invalid file.
nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

// trace.csv columns (DESIGN §4), shared by the contact and the Newton traces.
constexpr const char* kTraceHeader =
    "step,load_factor,attempt,outer,iteration,residual,increment_norm,active,entering,leaving,"
    "max_penetration,max_pressure,penalty,status\n";
}  // namespace

nlohmann::json make_summary(const core::Scene& scene, const core::Model* model,
                            const core::Results* r, const std::string& status,
                            const constraints::ContactReport* contact) {
  nlohmann::json j;
  j["status"] = status;
  j["scene"] = scene.path;
  j["title"] = scene.title;
  j["method"] = contact ? nlohmann::json(contact->method) : nlohmann::json();
  j["steps"] = 1;
  j["newton_iterations"] = 0;
  j["contact"] = nullptr;
  if (contact) {
    // Without slave edges (node-to-node gaps) there is no pressure field, only forces.
    const double nan = std::numeric_limits<double>::quiet_NaN();
    nlohmann::json c = {{"active_nodes", contact->active_nodes},
                        {"p_max", number(contact->has_surface ? contact->p_max : nan)},
                        {"length", number(contact->has_surface ? contact->length : nan)},
                        {"max_penetration", number(contact->max_penetration)},
                        {"total_force", number(contact->total_force)},
                        {"status", to_string(contact->status)},
                        {"message", contact->message},
                        {"iterations", contact->iterations},
                        {"detection_passes", contact->detection_passes},
                        {"rows", contact->rows},
                        {"slave_nodes", contact->nodes.size()},
                        {"seconds", contact->seconds},
                        {"detection_seconds", contact->detection_seconds},
                        {"pivot_ratio", number(contact->pivot_ratio)},
                        {"stiffness_max", number(contact->stiffness_max)},
                        {"pressure_recovered", contact->has_surface}};
    double k_max = 0;
    for (const auto& n : contact->nodes) k_max = std::max(k_max, n.penalty);
    c["penalty_max"] = k_max > 0 ? nlohmann::json(k_max) : nlohmann::json();
    c["penalty_history"] = contact->penalty_history;
    j["contact"] = c;
  }
  if (model) {
    j["mesh"] = {{"nodes", model->mesh.num_nodes()},
                 {"elements", model->mesh.num_elements()},
                 {"dofs", model->mesh.num_dofs()},
                 {"free_dofs", model->dofs.num_free()},
                 {"element", model->mesh.order == 1 ? "T3" : "T6"}};
    const auto [min_angle, skinny] = model->mesh.angle_quality();
    j["mesh"]["min_angle_deg"] = min_angle;
    j["mesh"]["skinny_triangles"] = skinny;
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
                   {"symbolic_s", r->solver.symbolic_seconds},
                   {"numeric_s", r->solver.numeric_seconds},
                   {"triangular_solve_s", r->solver.solve_seconds},
                   {"ordering", r->solver.ordering},
                   {"supernodal", r->solver.supernodal},
                   {"factor_nonzeros", r->solver.factor_nonzeros},
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
    // Relative errors against the reference values: contact results and probes by name.
    if (r) {
      std::vector<std::pair<std::string, double>> measured(r->probes.begin(), r->probes.end());
      if (contact) {
        measured.emplace_back("p_max", contact->p_max);
        measured.emplace_back("contact_length", contact->length);
        measured.emplace_back("total_force", contact->total_force);
      }
      nlohmann::json err = nlohmann::json::object();
      for (const auto& [key, value] : measured) {
        const auto it = scene.reference.find(key);
        if (it != scene.reference.end() && it->second != 0)
          err[key] = number((value - it->second) / it->second);
      }
      // Hertz references: the pressure profile as a whole (DESIGN's accuracy measure for the
      // time-to-accuracy benchmark), not only its peak and width.
      const auto hertz = hertz_reference(scene);
      if (contact && contact->has_surface && hertz)
        err["pressure_profile_l2"] =
            number(hertz_profile_error(pressure_profile(*contact), hertz->p0, hertz->b));
      ref["relative_error"] = err;
    }
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
  if (s.contains("load_factor"))
    os << "steps      " << s["steps"] << " load steps converged (load factor "
       << s["load_factor"].get<double>() << "), " << s["newton_iterations"]
       << " Newton iterations\n";
  if (s.contains("contact") && !s["contact"].is_null()) {
    const auto& c = s["contact"];
    os << "contact    " << s["method"].get<std::string>() << ": " << c["status"].get<std::string>()
       << " in " << c["iterations"] << " iterations, " << c["active_nodes"] << " of "
       << c["slave_nodes"] << " slave nodes active\n"
       << "           p_max " << c["p_max"].dump() << ", length " << c["length"].dump()
       << ", total force " << c["total_force"].get<double>()
       << ", max penetration " << c["max_penetration"].get<double>() << '\n';
    if (s.contains("reference") && s["reference"].contains("relative_error"))
      for (const auto& [key, e] : s["reference"]["relative_error"].items())
        if (!e.is_null()) {
          os << "reference  " << key;  // a derived measure (the profile's L2 error) has no value
          if (s["reference"].contains(key) && s["reference"][key].is_number())
            os << " " << s["reference"][key].get<double>();
          os << ": error " << std::showpos << 100.0 * e.get<double>() << std::noshowpos << " %\n";
        }
  }
  for (const auto& [name, value] : s["probes"].items())
    os << "probe      " << name << " = " << (value.is_null() ? std::string("null") : value.dump())
       << '\n';
  std::string files;  // what this run wrote ([output] may leave fields or charts out)
  for (const char* f : {"summary.json", "results.pvd", "nodes.csv", "contact.csv", "deformed.png"})
    if (std::filesystem::exists(out_dir + "/" + f)) files += (files.empty() ? "" : ", ") + std::string(f);
  os << "results    " << out_dir << "/ (" << files
     << (s.contains("load_factor") ? ", trace.csv; charts: contact2d trace " + out_dir : std::string())
     << ")\n";
  return os.str();
}

std::string contact_csv(const constraints::ContactReport& c) {
  std::ostringstream os;
  os << std::setprecision(12) << "node,x,y,gap,force,pressure,active,penalty\n";
  for (const auto& n : c.nodes)
    os << n.node + 1 << ',' << n.x.x() << ',' << n.x.y() << ',' << n.gap << ',' << n.force << ','
       << n.pressure << ',' << (n.active ? 1 : 0) << ',' << n.penalty << '\n';
  return os.str();
}

std::string trace_csv(const constraints::ContactReport& c) {
  std::ostringstream os;
  os << std::setprecision(10) << kTraceHeader;
  for (size_t i = 0; i < c.history.size(); ++i) {
    const auto& h = c.history[i];
    const bool last = i + 1 == c.history.size();
    os << "1,1,0,1," << h.iteration << ',' << h.residual << ",," << h.active << ',' << h.entering
       << ',' << h.leaving << ',' << h.max_penetration << ',';
    if (last) os << c.p_max;
    os << ',' << h.penalty << ',' << (last ? to_string(c.status) : "iterating") << '\n';
  }
  return os.str();
}

std::string newton_trace_csv(const std::vector<nonlinear::StepRecord>& steps) {
  std::ostringstream os;
  os << std::setprecision(10) << kTraceHeader;
  for (const auto& s : steps) {
    auto head = [&](int outer, int iteration) -> std::ostream& {
      return os << s.step << ',' << s.load_factor << ',' << s.attempt << ',' << outer << ','
                << iteration << ',';
    };
    if (s.contact.empty()) {
      const auto& norms = s.newton.residual_norms;
      for (size_t k = 0; k < norms.size(); ++k) {
        const bool last = k + 1 == norms.size();
        head(1, static_cast<int>(k)) << norms[k] << ',';
        if (last) os << s.newton.last_step;
        os << ",0,0,0,0,0,0," << (last ? to_string(s.newton.status) : "iterating") << '\n';
      }
      continue;
    }
    // Contact: the Newton iterations of each outer (active-set) iteration, numbered through the
    // attempt; the last row of an outer iteration carries its penetration and pressure, the
    // last row of the attempt its status.
    int base = 0;
    for (size_t o = 0; o < s.contact.size(); ++o) {
      const auto& it = s.contact[o];
      const auto& norms = it.newton.residual_norms;
      const size_t rows = std::max<size_t>(norms.size(), 1);
      for (size_t k = 0; k < rows; ++k) {
        const bool last = k + 1 == rows;
        head(it.outer, base + static_cast<int>(k)) << (norms.empty() ? 0.0 : norms[k]) << ',';
        if (last) os << it.newton.last_step;
        os << ',' << it.active << ',' << it.entering << ',' << it.leaving << ',';
        if (last) os << it.max_penetration << ',' << it.max_pressure;
        else os << ',';
        os << ',' << it.penalty << ','
           << (!last ? "iterating"
                     : to_string(o + 1 == s.contact.size() ? s.newton.status : it.newton.status))
           << '\n';
      }
      base += it.newton.iterations;
    }
  }
  return os.str();
}

/// One row per slave node and converged load step.
std::string contact_steps_csv(const std::vector<nonlinear::StepRecord>& steps) {
  std::ostringstream os;
  os << std::setprecision(12) << "step,load_factor,node,x,y,gap,force,pressure,active\n";
  for (const auto& s : steps) {
    if (s.newton.status != SolveStatus::kConverged) continue;
    for (const auto& n : s.contact_state.nodes)
      os << s.step << ',' << s.load_factor << ',' << n.node + 1 << ',' << n.x.x() << ','
         << n.x.y() << ',' << n.gap << ',' << n.force << ',' << n.pressure << ','
         << (n.active ? 1 : 0) << '\n';
  }
  return os.str();
}

}  // namespace c2d::app
