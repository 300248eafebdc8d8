#include "app/report/plot_run.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <map>
#include <sstream>
#include <string>

#include "app/report/csv_table.hpp"
#include "app/report/vtu_reader.hpp"
#include "core/errors.hpp"

namespace c2d::app {

namespace {

namespace fs = std::filesystem;

/// Files DIR/<prefix>NNNN.vtu by number.
std::map<int, std::string> numbered_vtus(const std::string& dir, const std::string& prefix) {
  std::map<int, std::string> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) != 0 || e.path().extension() != ".vtu") continue;
    const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - 4);
    if (!digits.empty() && digits.size() <= 9 &&  // beyond: no step number of a run (stoi throws)
        std::all_of(digits.begin(), digits.end(), ::isdigit))
      files[std::stoi(digits)] = e.path().string();
  }
  return files;
}

/// The VTU a request names (--cycle, --step, else the last step) and the suffix of its
/// pictures' stems.
std::pair<std::string, std::string> chosen_vtu(const PlotRequest& req,
                                               const std::map<int, std::string>& steps,
                                               const std::map<int, std::string>& cycles) {
  char suffix[32];
  if (req.cycle >= 0) {
    const auto it = cycles.find(req.cycle);
    if (it == cycles.end())
      throw InputError("--cycle " + std::to_string(req.cycle) + ": " + req.dir + " has " +
                       (cycles.empty() ? std::string("no adaptive cycles (cycle_NN.vtu)")
                                       : "cycles 0.." + std::to_string(cycles.rbegin()->first)));
    std::snprintf(suffix, sizeof suffix, "_cycle%02d", req.cycle);
    return {it->second, suffix};
  }
  if (req.step > 0) {
    const auto it = steps.find(req.step);
    if (it == steps.end())
      throw InputError("--step " + std::to_string(req.step) + ": " + req.dir + " has " +
                       (steps.empty() ? std::string("no step_NNNN.vtu")
                                      : "steps " + std::to_string(steps.begin()->first) + ".." +
                                            std::to_string(steps.rbegin()->first)));
    std::snprintf(suffix, sizeof suffix, "_step%04d", req.step);
    return {it->second, suffix};
  }
  if (steps.empty())
    throw InputError(req.dir + ": no step_NNNN.vtu (expected the output folder of contact2d run)");
  return {steps.rbegin()->second, ""};
}

/// --field: the names given ("all": every field; none: vm), each checked.
std::vector<std::string> requested_fields(const PlotRequest& req) {
  std::vector<std::string> fields =
      req.fields.empty() ? std::vector<std::string>{"vm"} : req.fields;
  if (std::find(fields.begin(), fields.end(), "all") != fields.end()) fields = plot_fields();
  for (const auto& f : fields)
    if (std::find(plot_fields().begin(), plot_fields().end(), f) == plot_fields().end())
      throw InputError("--field: expected " + plot_field_list() + " or all, found '" + f + "'");
  return fields;
}

/// adapt_meshes.png/svg: up to four cycles, the first, the last and evenly spaced ones between,
/// titled with their DOFs from adapt.csv when it is there.
void draw_adapt_meshes(const PlotRequest& req, const std::map<int, std::string>& cycles,
                       PlotWritten& out) {
  std::vector<int> ids;
  for (const auto& [k, path] : cycles) ids.push_back(k);
  std::vector<int> pick;
  const int n = static_cast<int>(ids.size()), panels = std::min(n, 4);
  for (int i = 0; i < panels; ++i) {
    const int id =
        ids[static_cast<size_t>(std::lround(static_cast<double>(i) * (n - 1) / (panels - 1)))];
    if (pick.empty() || pick.back() != id) pick.push_back(id);
  }
  std::map<int, std::string> dofs;
  if (fs::exists(req.dir + "/adapt.csv")) {
    const CsvTable t = read_csv(req.dir + "/adapt.csv");
    const int cc = t.column("cycle"), cd = t.column("dofs");
    for (size_t r = 0; r < t.rows.size(); ++r)
      dofs[static_cast<int>(t.number(r, cc))] = t.rows[r][cd];
  }
  std::vector<std::pair<std::string, VtuData>> meshes;
  std::string listed;
  for (int id : pick) {
    VtuData m = read_vtu(cycles.at(id));
    const std::string size =
        dofs.count(id) ? dofs[id] + " DOFs" : std::to_string(m.cells.size()) + " elements";
    meshes.emplace_back("cycle " + std::to_string(id) + ": " + size, std::move(m));
    listed += (listed.empty() ? "" : ", ") + std::to_string(id);
  }
  out.error = plot_mesh_comparison(meshes, req.options.zoom, req.dir, "adapt_meshes");
  if (out.error.empty())
    out.written.emplace_back("adapt_meshes", "element edges of cycles " + listed);
}

}  // namespace

PlotWritten plot_run(const PlotRequest& req) {
  if (!fs::is_directory(req.dir))
    throw InputError(req.dir + ": not a folder (expected the output folder of contact2d run)");
  const auto steps = numbered_vtus(req.dir, "step_"), cycles = numbered_vtus(req.dir, "cycle_");
  const auto [file, suffix] = chosen_vtu(req, steps, cycles);
  const std::vector<std::string> fields = requested_fields(req);
  const VtuData vtu = read_vtu(file);
  PlotWritten out;
  for (const auto& f : fields) {
    PlotOptions o = req.options;
    o.field = f;
    const std::string stem = "plot_" + f + suffix;
    const PlotSummary s = plot_field(vtu, o, req.dir, stem);
    if (!s.error.empty()) {
      out.error = s.error;
      return out;
    }
    std::ostringstream what;
    what << std::setprecision(5) << fs::path(file).filename().string() << ", ";
    if (f == "error")
      what << s.above_one << " of " << s.elements << " elements with xi_e > 1 (max " << s.max
           << ")";
    else
      what << f << " from " << s.min << " to " << s.max;
    out.written.emplace_back(stem, what.str());
  }
  if (cycles.size() >= 2) draw_adapt_meshes(req, cycles, out);
  return out;
}

}  // namespace c2d::app
