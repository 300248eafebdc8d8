// The error-driven adaptive loop: solve, estimate (Zienkiewicz-Zhu), remesh every body with the
// optimal-mesh sizes through gmsh, solve again, until the global parameter ξ_g <= 1.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/run/solve_scene.hpp"
#include "core/scene.hpp"

namespace c2d::app {

struct AdaptCycle {
  int cycle = 0;  ///< 0 = the scene's own mesh
  int nodes = 0, elements = 0, dofs = 0;
  double global_parameter = 0;  ///< ξ_g
  double max_local = 0;         ///< max ξ_e
  double relative_error = 0;    ///< ||e|| / ||U||
  double h_min = 0, h_max = 0;  ///< element edge lengths
  double seconds = 0;           ///< mesh + solve + recovery of the cycle
  std::string status;           ///< converged | the solver's failure
  std::map<std::string, double> probes;
};

struct AdaptRun {
  std::vector<AdaptCycle> cycles;
  std::unique_ptr<SceneRun> last;  ///< the final cycle's model and results
  bool reached = false;            ///< ξ_g <= 1 on the final cycle
  std::string stop;                ///< why the loop stopped, one line
};

/// Runs the loop with `scene.adapt` (target η, cycle limit, size bounds). Nothing is carried
/// from one mesh to the next but the size field: each cycle solves the scene (the whole load
/// path of a load-stepped analysis) on its new mesh. `on_cycle` sees every cycle's run as soon
/// as it is solved (writing its VTU, progress). Throws InputError for scenes it cannot remesh
/// (legacy meshes, .msh files, point clouds).
AdaptRun solve_adaptive(const core::Scene& scene, const std::string& method,
                        const std::function<void(const std::string&)>& progress,
                        const std::function<void(const AdaptCycle&, const SceneRun&)>& on_cycle);

/// summary.json's adapt section: target, max_cycles, reached, stop, and per cycle its DOFs,
/// elements, ξ_g, max ξ_e, relative error, smallest element, time, status and probes.
nlohmann::json adapt_summary(const core::AdaptSpec& spec, const AdaptRun& run);

/// adapt.csv: cycle, nodes, elements, dofs, xi_g, xi_max, relative_error, h_min, h_max,
/// seconds, status, then one column per probe.
std::string adapt_csv(const std::vector<AdaptCycle>& cycles);

}  // namespace c2d::app
