// The verbs that draw from a finished run's files: trace and plot.
#include <array>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "app/cli/verbs.hpp"
#include "app/output_folder.hpp"
#include "app/report/plot_run.hpp"
#include "app/report/trace_charts.hpp"
#include "core/errors.hpp"

namespace c2d::app {

namespace {

/// What a chart verb wrote into DIR (stem, what it shows), then its error if any: the exit code.
int report_charts(const std::string& dir,
                  const std::vector<std::pair<std::string, std::string>>& written,
                  const std::string& error) {
  std::vector<std::string> files;
  for (const auto& [stem, what] : written) {
    std::cout << "wrote " << dir << "/" << stem << ".png and .svg: " << what << "\n";
    files.insert(files.end(), {stem + ".png", stem + ".svg"});
  }
  add_to_run_manifest(dir, files);  // a later run into DIR may replace them
  if (!error.empty()) {
    std::cerr << "error: " << error << "\n";
    return kExitSolveFailed;
  }
  return kExitOk;
}

}  // namespace

int cmd_trace(const Options& o) {
  const TraceCharts charts = draw_trace_charts(o.scene);
  return report_charts(o.scene, charts.written, charts.error);
}

int cmd_plot(const Options& o) {
  PlotRequest req;
  req.dir = o.scene;
  req.fields = o.fields;
  req.step = o.step;
  req.cycle = o.cycle;
  req.options.edges = o.edges;
  req.options.levels = o.plot_levels;
  if (!o.zoom.empty()) {
    std::array<double, 4> z{};
    std::stringstream list(o.zoom);
    std::string item;
    int k = 0;
    for (; std::getline(list, item, ','); ++k) {
      char* end = nullptr;
      const double v = std::strtod(item.c_str(), &end);
      if (k >= 4 || item.empty() || *end != '\0')
        throw InputError("--zoom: expected x0,y0,x1,y1 (four numbers), found '" + o.zoom + "'");
      z[k] = v;
    }
    if (k != 4 || !(z[2] > z[0] && z[3] > z[1]))
      throw InputError("--zoom: expected x0,y0,x1,y1 with x1 > x0 and y1 > y0, found '" + o.zoom +
                       "'");
    req.options.zoom = z;
  }
  if (!o.deformed.empty()) {
    char* end = nullptr;
    req.options.deformed = o.deformed == "auto" ? -1.0 : std::strtod(o.deformed.c_str(), &end);
    if (o.deformed != "auto" && (*end != '\0' || !(req.options.deformed > 0)))
      throw InputError("--deformed: expected a positive scale or auto, found '" + o.deformed + "'");
  }
  const PlotWritten w = plot_run(req);
  return report_charts(o.scene, w.written, w.error);
}

}  // namespace c2d::app
