#include "app/run/adapt.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iomanip>
#include <set>
#include <sstream>

#include "core/errors.hpp"
#include "core/size_field.hpp"

namespace c2d::app {

namespace {

AdaptCycle describe(int cycle, const SceneRun& run, double seconds) {
  AdaptCycle c;
  c.cycle = cycle;
  const core::Mesh& mesh = run.model.mesh;
  c.nodes = mesh.num_nodes();
  c.elements = mesh.num_elements();
  c.dofs = mesh.num_dofs();
  const auto& est = run.results.error;
  c.global_parameter = est.global_parameter;
  c.relative_error = est.relative_error;
  for (double xi : est.local_parameter) c.max_local = std::max(c.max_local, xi);
  c.h_min = 1e300;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const double h = core::element_size(mesh, e);
    c.h_min = std::min(c.h_min, h);
    c.h_max = std::max(c.h_max, h);
  }
  c.seconds = seconds;
  c.status =
      run.results.status == SolveStatus::kConverged ? "converged" : to_string(run.results.status);
  c.probes = run.results.probes;
  return c;
}

}  // namespace

AdaptRun solve_adaptive(const core::Scene& scene_in, const std::string& method,
                        const std::function<void(const std::string&)>& progress,
                        const std::function<void(const AdaptCycle&, const SceneRun&)>& on_cycle) {
  auto say = [&](const std::string& text) {
    if (progress) progress(text);
  };
  if (scene_in.explicit_model)
    throw InputError(scene_in.path +
                     ": adapt: a legacy data file's mesh is given node by node; "
                     "adaptivity needs bodies meshed from shapes");
  for (const auto& b : scene_in.bodies) {
    if (!b.msh_file.empty())
      throw InputError(b.at.where + ": adapt: body '" + b.name +
                       "' reads a .msh file; adaptivity needs a shape gmsh can mesh again");
    if (b.shape.type == "points")
      throw InputError(b.at.where + ": adapt: body '" + b.name +
                       "' is a point cloud, triangulated as given; adaptivity needs a shape");
  }
  core::Scene scene = scene_in;
  const core::AdaptSpec& spec = scene_in.adapt;
  scene.analysis.target_error = spec.target;  // ξ is measured against the adaptive target
  AdaptRun out;
  for (int cycle = 0; cycle < spec.max_cycles; ++cycle) {
    const auto t0 = std::chrono::steady_clock::now();
    say("adapt cycle " + std::to_string(cycle));
    auto run = solve_scene(scene, method, progress);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    AdaptCycle c = describe(cycle, *run, seconds);
    out.cycles.push_back(c);
    if (on_cycle) on_cycle(c, *run);
    char line[240];
    std::snprintf(line, sizeof line, "adapt cycle %d: %d DOFs, xi_g %.3g, max xi_e %.3g, %.2f s",
                  cycle, c.dofs, c.global_parameter, c.max_local, seconds);
    say(line);
    const bool solved = run->results.status == SolveStatus::kConverged;
    out.last = std::move(run);
    if (!solved) {
      out.stop = "cycle " + std::to_string(cycle) + " did not solve (" + c.status + ")";
      return out;
    }
    if (c.global_parameter <= 1.0) {
      out.reached = true;
      std::snprintf(line, sizeof line,
                    "xi_g = %.3g <= 1 after %d cycle%s: relative error %.3g %% <= target %.3g %%",
                    c.global_parameter, cycle, cycle == 1 ? "" : "s", 100 * c.relative_error,
                    100 * spec.target);
      out.stop = line;
      return out;
    }
    if (cycle + 1 == spec.max_cycles) break;
    // The next mesh: one size field per body from this cycle's local parameters.
    const core::Mesh& mesh = out.last->model.mesh;
    const auto fields =
        core::optimal_size_fields(mesh, out.last->results.error.local_parameter,
                                  static_cast<int>(scene.bodies.size()), spec.limits);
    for (size_t b = 0; b < scene.bodies.size(); ++b)
      scene.bodies[b].size_field = std::make_shared<core::SizeField>(fields[b]);
  }
  char line[200];
  std::snprintf(
      line, sizeof line,
      "cycle limit %d reached with xi_g = %.3g > 1 (relative error %.3g %%, target %.3g %%)",
      spec.max_cycles, out.cycles.back().global_parameter, 100 * out.cycles.back().relative_error,
      100 * spec.target);
  out.stop = line;
  return out;
}

nlohmann::json adapt_summary(const core::AdaptSpec& spec, const AdaptRun& run) {
  nlohmann::json a = {{"target", spec.target},
                      {"max_cycles", spec.max_cycles},
                      {"reached", run.reached},
                      {"stop", run.stop}};
  for (const auto& c : run.cycles)
    a["cycles"].push_back({{"cycle", c.cycle},
                           {"dofs", c.dofs},
                           {"elements", c.elements},
                           {"xi_g", c.global_parameter},
                           {"xi_max", c.max_local},
                           {"relative_error", c.relative_error},
                           {"h_min", c.h_min},
                           {"seconds", c.seconds},
                           {"status", c.status},
                           {"probes", c.probes}});
  return a;
}

std::string adapt_csv(const std::vector<AdaptCycle>& cycles) {
  std::set<std::string> names;
  for (const auto& c : cycles)
    for (const auto& [k, v] : c.probes) names.insert(k);
  std::ostringstream os;
  os << std::setprecision(10)
     << "cycle,nodes,elements,dofs,xi_g,xi_max,relative_error,h_min,h_max,seconds,status";
  for (const auto& n : names) os << ',' << n;
  os << '\n';
  for (const auto& c : cycles) {
    os << c.cycle << ',' << c.nodes << ',' << c.elements << ',' << c.dofs << ','
       << c.global_parameter << ',' << c.max_local << ',' << c.relative_error << ',' << c.h_min
       << ',' << c.h_max << ',' << c.seconds << ',' << c.status;
    for (const auto& n : names) {
      os << ',';
      if (const auto it = c.probes.find(n); it != c.probes.end()) os << it->second;
    }
    os << '\n';
  }
  return os.str();
}

}  // namespace c2d::app
