#include "app/report/summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

#include "app/report/hertz.hpp"
#include "app/report/pressure_profile.hpp"
#include "app/report/units.hpp"
#include "core/springs.hpp"

#include <sys/resource.h>
#include <unistd.h>

namespace c2d::app {

namespace {

// JSON has no NaN/inf: a non-finite number becomes null rather than an invalid file.
nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

/// What a run that ended with its status should still be told: a final state that penetrates
/// beyond the physical limit (a regularised method's converged answer to a soft problem).
nlohmann::json contact_warnings(const constraints::ContactReport& contact) {
  nlohmann::json w = nlohmann::json::array();
  if (contact.measured_penetration > contact.penetration_limit) {
    char text[320];
    std::snprintf(text, sizeof text,
                  "contact: the final state penetrates by %.4g, beyond the physical limit %.4g "
                  "(penetration_limit x the shortest contact edge); a regularised method's "
                  "answer: raise penalty.k or use an exact method",
                  contact.measured_penetration, contact.penetration_limit);
    w.push_back(text);
  }
  if (contact.nodal_penetration > contact.penetration_limit &&
      !(contact.measured_penetration > contact.penetration_limit)) {
    char text[320];
    std::snprintf(text, sizeof text,
                  "contact: a slave node lies %.4g below the deformed master surface, beyond the "
                  "physical limit %.4g, although the contact rows hold (a linear analysis's "
                  "linearised gaps, or mortar's weighted ones, on a coarse or strongly curved "
                  "surface)",
                  contact.nodal_penetration, contact.penetration_limit);
    w.push_back(text);
  }
  if (contact.fallback_steps > 0)
    w.push_back("contact: " + std::to_string(contact.fallback_steps) + " load step" +
                (contact.fallback_steps > 1 ? "s" : "") + " finished by " +
                contact.fallback_method + ", " + contact.method +
                "'s fallback (the same solution: docs/scene.md); the last handed over because " +
                contact.fallback_reason);
  return w;
}

nlohmann::json contact_section(const constraints::ContactReport& contact) {
  // Without slave edges (node-to-node gaps) there is no pressure field, only forces.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  nlohmann::json c = {{"active_nodes", contact.active_nodes},
                      {"p_max", number(contact.has_surface ? contact.p_max : nan)},
                      {"length", number(contact.has_surface ? contact.length : nan)},
                      {"max_penetration", number(contact.max_penetration)},
                      {"measured_penetration", number(contact.measured_penetration)},
                      {"penetration_tolerance", number(contact.penetration_tolerance)},
                      {"nodal_penetration", number(contact.nodal_penetration)},
                      {"penetration_limit", number(contact.penetration_limit)},
                      {"total_force", number(contact.total_force)},
                      {"resultant", {number(contact.resultant.x()), number(contact.resultant.y())}},
                      {"status", to_string(contact.status)},
                      {"message", contact.message},
                      {"iterations", contact.iterations},
                      {"fallback_steps", contact.fallback_steps},
                      {"fallback_method", contact.fallback_method},
                      {"fallback_reason", contact.fallback_reason},
                      {"detection_passes", contact.detection_passes},
                      {"rows", contact.rows},
                      {"slave_nodes", contact.nodes.size()},
                      {"seconds", contact.seconds},
                      {"detection_seconds", contact.detection_seconds},
                      {"pivot_ratio", number(contact.pivot_ratio)},
                      {"stiffness_max", number(contact.stiffness_max)},
                      {"pressure_recovered", contact.has_surface}};
  double k_max = 0;
  for (const auto& n : contact.nodes) k_max = std::max(k_max, n.penalty);
  c["penalty_max"] = k_max > 0 ? nlohmann::json(k_max) : nlohmann::json();
  c["penalty_history"] = contact.penalty_history;
  if (contact.friction) {
    double q_max = 0.0;
    for (const auto& n : contact.nodes) q_max = std::max(q_max, std::abs(n.shear));
    c["friction"] = {{"stick_nodes", contact.stick_nodes},
                     {"slip_nodes", contact.slip_nodes},
                     {"stick_length", number(contact.has_surface ? contact.stick_length : nan)},
                     {"shear_max", number(contact.has_surface ? q_max : nan)},
                     {"tangential_force", number(contact.tangent_force)}};
  }
  return c;
}

/// The [[plate]]s: motion of the reference point and the force and moment each transmits.
nlohmann::json plates_section(const constraints::ContactReport& contact) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& pl : contact.plates)
    list.push_back({{"name", pl.name},
                    {"ux", number(pl.u.x())},
                    {"uy", number(pl.u.y())},
                    {"rotation", number(pl.rotation)},
                    {"force", {number(pl.force.x()), number(pl.force.y())}},
                    {"moment", number(pl.moment)}});
  return list;
}

/// The [[constraint]] tables: per table its rows, largest multiplier (force) and residual.
nlohmann::json constraints_section(const constraints::ContactReport& contact) {
  nlohmann::json list = nlohmann::json::array();
  for (size_t k = 0; k < contact.equality_names.size(); ++k) {
    int rows = 0;
    double force = 0.0, residual = 0.0;
    for (const auto& e : contact.equalities)
      if (e.owner == static_cast<int>(k)) {
        ++rows;
        force = std::max(force, std::abs(e.multiplier));
        residual = std::max(residual, std::abs(e.residual));
      }
    list.push_back({{"name", contact.equality_names[k]},
                    {"type", contact.equality_types[k]},
                    {"rows", rows},
                    {"max_force", number(force)},
                    {"max_residual", number(residual)}});
  }
  return list;
}

/// Per [[spring]]: how many springs it made and the largest axial force (tension positive;
/// to ground: the force's size) at the final state.
nlohmann::json springs_section(const core::Model& model, const core::Results& r, bool finite) {
  nlohmann::json list = nlohmann::json::array();
  for (const core::Spring& s : model.springs) {
    if (list.empty() || list.back()["name"] != s.name)
      list.push_back({{"name", s.name}, {"count", 0}, {"max_force", 0.0}});
    nlohmann::json& e = list.back();
    e["count"] = e["count"].get<int>() + 1;
    const double f = r.displacement.size() == model.dofs.num_dofs()
                         ? core::spring_force(model, s, r.displacement, finite)
                         : 0.0;
    if (std::abs(f) > std::abs(e["max_force"].get<double>())) e["max_force"] = f;
  }
  return list;
}

nlohmann::json mesh_section(const core::Model& model) {
  nlohmann::json m = {{"nodes", model.mesh.num_nodes()},
                      {"elements", model.mesh.num_elements()},
                      {"dofs", model.mesh.num_dofs()},
                      {"free_dofs", model.dofs.num_free()},
                      {"element", model.mesh.order == 1 ? "T3" : "T6"}};
  const auto [min_angle, skinny] = model.mesh.angle_quality();
  m["min_angle_deg"] = min_angle;
  m["skinny_triangles"] = skinny;
  return m;
}

nlohmann::json solver_section(const core::Results& r) {
  return {{"backend", r.solver.backend},
          {"status", to_string(r.solver.status)},
          {"relative_residual", number(r.solver.relative_residual)},
          {"pivot_ratio", number(r.solver.pivot_ratio)},
          {"symbolic_analyses", r.solver.symbolic_analyses},
          {"numeric_factorizations", r.solver.numeric_factorizations},
          {"symbolic_s", r.solver.symbolic_seconds},
          {"numeric_s", r.solver.numeric_seconds},
          {"triangular_solve_s", r.solver.solve_seconds},
          {"ordering", r.solver.ordering},
          {"supernodal", r.solver.supernodal},
          {"factor_nonzeros", r.solver.factor_nonzeros},
          {"separator", r.solver.separator},
          {"message", r.solver.message}};
}

/// The process so far, as a study that merges case folders from other machines needs it:
/// wall time since the process started (/proc/self/stat's start time against /proc/uptime,
/// 10 ms resolution, library loading included) and peak resident memory (getrusage).
nlohmann::json process_section() {
  nlohmann::json j = nlohmann::json::object();
  struct rusage use {};
  if (::getrusage(RUSAGE_SELF, &use) == 0) j["peak_rss_mb"] = use.ru_maxrss / 1024.0;
  std::ifstream stat("/proc/self/stat"), uptime("/proc/uptime");
  std::string text;
  double up = 0.0;
  if (std::getline(stat, text) && (uptime >> up)) {
    // Field 22, counted after the command name's closing parenthesis (field 2 may hold spaces).
    std::istringstream rest(text.substr(text.rfind(')') + 2));
    std::string field;
    for (int k = 3; k <= 22 && rest >> field; ++k)
      if (k == 22) j["wall_s"] = up - std::stod(field) / static_cast<double>(::sysconf(_SC_CLK_TCK));
  }
  return j;
}

/// time_s, solver, error and probes.
void add_results(nlohmann::json& j, const core::Results& r) {
  j["time_s"] = {{"mesh", r.time.mesh},     {"assemble", r.time.assemble},
                 {"solve", r.time.solve},   {"recovery", r.time.recovery},
                 {"output", r.time.output}, {"total", r.time.total}};
  j["solver"] = solver_section(r);
  j["error"] = {{"global_parameter", number(r.error.global_parameter)},
                {"energy_norm", number(r.error.energy_norm)},
                {"error_norm", number(r.error.error_norm)},
                {"relative_error", number(r.error.relative_error)},
                {"target", r.error.target}};
  nlohmann::json probes = nlohmann::json::object();
  for (const auto& [name, value] : r.probes) probes[name] = number(value);
  j["probes"] = probes;
}

/// Relative errors against the reference values: contact results and probes by name, and for
/// Hertz references the pressure profile as a whole (DESIGN's accuracy measure for the
/// time-to-accuracy benchmark), not only its peak and width.
nlohmann::json reference_errors(const core::Scene& scene, const core::Results& r,
                                const constraints::ContactReport* contact) {
  std::vector<std::pair<std::string, double>> measured(r.probes.begin(), r.probes.end());
  if (contact) {
    measured.emplace_back("p_max", contact->p_max);
    measured.emplace_back("contact_length", contact->length);
    measured.emplace_back("total_force", contact->total_force);
    if (contact->friction) {
      measured.emplace_back("stick_length", contact->stick_length);
      measured.emplace_back("tangential_force", std::abs(contact->tangent_force));
    }
  }
  nlohmann::json err = nlohmann::json::object();
  for (const auto& [key, value] : measured) {
    const auto it = scene.reference.find(key);
    if (it != scene.reference.end() && it->second != 0)
      err[key] = number((value - it->second) / it->second);
  }
  const auto hertz = hertz_reference(scene);
  if (contact && contact->has_surface && hertz) {
    const auto profile = pressure_profile(*contact);
    err["pressure_profile_l2"] = number(hertz_profile_error(profile, hertz->p0, hertz->b));
    err["pressure_profile_inner_l2"] =
        number(hertz_inner_profile_error(profile, hertz->p0, hertz->b));
  }
  // Cattaneo–Mindlin: the shear profile, taken in the direction of the total tangential force.
  const auto cm = cattaneo_reference(scene);
  if (contact && contact->friction && contact->has_surface && cm) {
    std::vector<Vec2> x;
    for (const auto& n : contact->nodes) x.push_back(n.x);
    const int axis = spread_axis(x);
    const double sign = contact->tangent_force < 0 ? -1.0 : 1.0;
    std::vector<std::pair<double, double>> pts;
    for (const auto& n : contact->nodes) pts.emplace_back(n.x[axis], sign * n.shear);
    err["shear_profile_l2"] =
        number(cattaneo_mindlin_error(pts, cm->mu, cm->hertz.p0, cm->hertz.b, cm->c));
  }
  return err;
}

nlohmann::json reference_section(const SummaryParts& p) {
  nlohmann::json ref = {{"kind", p.scene.reference_kind}};
  for (const auto& [k, v] : p.scene.reference) ref[k] = v;
  if (p.results) ref["relative_error"] = reference_errors(p.scene, *p.results, p.contact);
  return ref;
}

double global(const core::Results& r, const char* key) {
  const auto it = r.globals.find(key);
  return it == r.globals.end() ? 0.0 : it->second;
}

}  // namespace

std::string run_status(const core::Results& results) {
  if (results.status == SolveStatus::kConverged) return "converged";
  return std::string("failed: ") +
         (results.status == SolveStatus::kFailed ? std::string()
                                                 : std::string(to_string(results.status)) + ": ") +
         results.message;
}

nlohmann::json make_summary(const SummaryParts& p) {
  nlohmann::json j;
  j["status"] = p.status;
  j["scene"] = p.scene.path;
  j["title"] = p.scene.title;
  if (!p.scene.units.empty()) j["units"] = p.scene.units;
  j["method"] = p.contact ? nlohmann::json(p.contact->method) : nlohmann::json();
  j["steps"] = 1;
  j["newton_iterations"] = 0;
  j["contact"] = p.contact ? contact_section(*p.contact) : nlohmann::json();
  j["warnings"] = p.contact ? contact_warnings(*p.contact) : nlohmann::json::array();
  if (p.contact && !p.contact->equality_names.empty())
    j["constraints"] = constraints_section(*p.contact);
  if (p.contact && !p.contact->plates.empty()) j["plates"] = plates_section(*p.contact);
  if (p.model) j["mesh"] = mesh_section(*p.model);
  if (p.model && p.results && !p.model->springs.empty())
    j["springs"] = springs_section(*p.model, *p.results, p.scene.analysis.geometric_nonlinearity);
  if (p.results)
    add_results(j, *p.results);
  else
    j["probes"] = nlohmann::json::object();
  if (!p.scene.reference_kind.empty()) j["reference"] = reference_section(p);
  if (p.steps && p.results) {
    int newton = 0, factorizations = 0;
    for (const auto& s : *p.steps) newton += s.newton.iterations, factorizations += s.factorizations;
    const int steps = static_cast<int>(global(*p.results, "steps"));
    j["steps"] = steps;
    j["newton_iterations"] = newton;
    // Every attempt's work (cut back ones too) over the converged steps.
    j["per_step"] = {{"newton_iterations", steps > 0 ? double(newton) / steps : 0.0},
                     {"factorizations", steps > 0 ? double(factorizations) / steps : 0.0}};
    j["load_factor"] = global(*p.results, "load_factor");
  }
  if (!p.adapt.is_null()) j["adapt"] = p.adapt;
  j["process"] = process_section();
  return j;
}

namespace {

/// v to `digits` significant figures (a null json value as "null").
std::string sig(const nlohmann::json& v, int digits) {
  if (!v.is_number()) return v.is_null() ? "null" : v.dump();
  std::ostringstream os;
  os << std::setprecision(digits) << v.get<double>();
  return os.str();
}

void contact_lines(const nlohmann::json& s, const Units& u, std::ostringstream& os) {
  const auto& c = s["contact"];
  os << "contact    " << s["method"].get<std::string>() << ": " << c["status"].get<std::string>()
     << " in " << c["iterations"] << " iterations, " << c["active_nodes"] << " of "
     << c["slave_nodes"] << " slave nodes active\n"
     << "           p_max " << sig(c["p_max"], 5) << unit_suffix(u.stress) << ", length "
     << sig(c["length"], 5) << unit_suffix(u.length) << ", total force " << sig(c["total_force"], 5)
     << unit_suffix(u.force) << ", max penetration " << sig(c["max_penetration"], 3) << unit_suffix(u.length)
     << " (measured at the final positions: " << sig(c["measured_penetration"], 3) << ")\n";
  if (!s.contains("reference") || !s["reference"].contains("relative_error")) return;
  for (const auto& [key, e] : s["reference"]["relative_error"].items())
    if (!e.is_null()) {
      os << "reference  " << key;  // a derived measure (the profile's L2 error) has no value
      if (s["reference"].contains(key) && s["reference"][key].is_number())
        os << " " << sig(s["reference"][key], 6);
      const double percent = 100.0 * e.get<double>();
      os << ": error " << (percent >= 0 ? "+" : "") << sig(percent, 3) << " %\n";
    }
}

}  // namespace

std::string terminal_summary(const nlohmann::json& s, const std::string& out_dir,
                             const std::string& files_dir) {
  std::ostringstream os;
  const Units u = parse_units(s.value("units", std::string()));
  os << "status     " << s["status"].get<std::string>() << '\n';
  if (s.contains("mesh"))
    os << "mesh       " << s["mesh"]["element"].get<std::string>() << ", " << s["mesh"]["nodes"]
       << " nodes, " << s["mesh"]["elements"] << " elements, " << s["mesh"]["dofs"] << " DOFs\n";
  if (s.contains("time_s"))
    os << "time       mesh " << sig(s["time_s"]["mesh"], 3) << " s, assemble "
       << sig(s["time_s"]["assemble"], 3) << " s, solve " << sig(s["time_s"]["solve"], 3)
       << " s, total " << sig(s["time_s"]["total"], 3) << " s\n";
  if (s["status"] == "converged" && s.contains("error") && !s["error"]["relative_error"].is_null())
    os << "ZZ error   " << sig(100.0 * s["error"]["relative_error"].get<double>(), 3)
       << " % (global parameter " << sig(s["error"]["global_parameter"], 3) << " for target "
       << sig(100.0 * s["error"]["target"].get<double>(), 3) << " %)\n";
  if (s.contains("load_factor"))
    os << "steps      " << s["steps"] << " load steps converged (load factor "
       << sig(s["load_factor"], 6) << "), " << s["newton_iterations"] << " Newton iterations\n";
  if (s.contains("constraints"))
    for (const auto& e : s["constraints"])
      os << "constraint " << e["name"].get<std::string>() << " (" << e["type"].get<std::string>()
         << ", " << s["method"].get<std::string>() << "): " << e["rows"] << " rows, largest force "
         << sig(e["max_force"], 5) << unit_suffix(u.force) << ", largest residual "
         << sig(e["max_residual"], 3) << unit_suffix(u.length) << "\n";
  if (s.contains("contact") && !s["contact"].is_null() && s["contact"]["slave_nodes"] != 0)
    contact_lines(s, u, os);
  for (const auto& [name, value] : s["probes"].items())
    os << "probe      " << name << " = " << sig(value, 6) << '\n';
  if (s.contains("warnings") && s["warnings"].is_array())
    for (const auto& w : s["warnings"])
      if (w.is_string()) os << "warning    " << w.get<std::string>() << '\n';
  std::string files;  // what this run wrote ([output] may leave fields or charts out)
  for (const char* f : {"summary.json", "results.pvd", "nodes.csv", "contact.csv", "deformed.png"})
    if (std::filesystem::exists((files_dir.empty() ? out_dir : files_dir) + "/" + f))
      files += (files.empty() ? "" : ", ") + std::string(f);
  os << "results    " << out_dir << "/ (" << files
     << (s.contains("load_factor") ? ", trace.csv; charts: contact2d trace " + out_dir
                                   : std::string())
     << ")\n";
  return os.str();
}

}  // namespace c2d::app
