// contact2d: the command-line program. Thin: parses arguments, loads the scene, calls the
// library, prints and writes results.
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "app/run/adapt.hpp"
#include "app/studies/bench.hpp"
#include "app/studies/calibrate.hpp"
#include "app/report/charts.hpp"
#include "app/report/field_plot.hpp"
#include "app/report/summary.hpp"
#include "app/run/run_output.hpp"
#include "app/run/solve_scene.hpp"
#include "app/studies/studies.hpp"
#include "app/report/trace_charts.hpp"
#include "constraints/contact_scene.hpp"
#include "core/errors.hpp"
#include "core/model.hpp"
#include "core/probes.hpp"
#include "core/scene.hpp"
#include "core/writers.hpp"
#include "nonlinear/linear_static.hpp"
#include "nonlinear/load_stepper.hpp"

namespace fs = std::filesystem;
using namespace c2d;

namespace {

constexpr int kExitOk = 0, kExitSolveFailed = 1, kExitBadInput = 2;

const char* kMainHelp =
    "contact2d - finite-element contact between 2D elastic bodies\n"
    "\n"
    "usage: contact2d <verb> [options]\n"
    "  run SCENE      solve a scene (TOML, or a legacy .dat data file) and write results\n"
    "  mesh SCENE     mesh the scene's bodies and write mesh.vtu\n"
    "  info SCENE     list bodies, materials, node/edge sets, supports, loads and probes\n"
    "  compare SCENE  every contact method on the same model, over refinement levels: table,\n"
    "                 verdict, accuracy-against-time, pressure and penetration charts\n"
    "  sweep SCENE    one scene key over a range (e.g. the penalty stiffness): table, the\n"
    "                 range meeting an accuracy, charts\n"
    "  calibrate SCENE  fit scene parameters to measured probe values (Ceres least squares)\n"
    "  trace OUTDIR   charts of a finished run: contact activation per load step, contact\n"
    "                 force against load factor, Newton residual history\n"
    "  bench          the benchmark ladder (10k to 1M DOFs, every method): bench.csv,\n"
    "                 bench.md with targets against measured figures, charts\n"
    "  plot OUTDIR    pictures of a finished run: filled contours of a field on the (deformed)\n"
    "                 mesh, the ZZ error map, meshes of adaptive cycles side by side\n"
    "\n"
    "Every verb has --help. Exit codes: 0 ok, 1 solve failed (partial results kept),\n"
    "2 bad input.\n";

const char* kRunHelp =
    "usage: contact2d run SCENE [--method M] [--set key=value ...] [--out DIR] [--quiet]\n"
    "                          [--adapt [target=0.05] [max_cycles=8]]\n"
    "\n"
    "Solves SCENE and writes into DIR (default: the scene's output.dir, else out/<scene>):\n"
    "  summary.json   status, mesh, times, error estimate, probes (stable keys)\n"
    "  results.pvd    + step_0001.vtu for ParaView\n"
    "  nodes.csv      displacements, smoothed stresses and reactions per node\n"
    "  deformed.png   deformed mesh coloured by von Mises (and .svg)\n"
    "  run.log        what was printed\n"
    "  contact.csv    gap, force and recovered pressure per slave node (contact scenes)\n"
    "  trace.csv      one row per Newton / active-set iteration of every load step: residual,\n"
    "                 active set, entering, leaving, penetration, pressure, status\n"
    "  contact_steps.csv  per load step and slave node: gap, force, pressure, active\n"
    "  adapt.csv      adaptive runs: per cycle DOFs, xi_g, max xi_e, error, time, probes;\n"
    "                 cycle_NN.vtu (listed in adapt.pvd) holds each cycle's mesh and fields\n"
    "\n"
    "  --method M       contact enforcement: penalty | adaptive_penalty | lagrange | auglag |\n"
    "                   ipopt | ssn (overrides the scene's [[contact]] method)\n"
    "  --set key=value  override a scene key, e.g. --set analysis.element=T3,\n"
    "                   --set body.beam.mesh.size=0.05 (array entries by index or name)\n"
    "  --adapt          error-driven h-adaptivity (also the scene's [adapt] table): solve,\n"
    "                   ZZ estimate, remesh with h_new = h / xi_e^(1/p), until xi_g <= 1 or\n"
    "                   max_cycles solves; target is the relative energy-norm error;\n"
    "                   max_shrink=0.2 and max_growth=2 bound h_new / h per cycle\n"
    "  --out DIR        output folder\n"
    "  --quiet          print nothing but errors\n";

const char* kMeshHelp =
    "usage: contact2d mesh SCENE [--set key=value ...] [--out DIR]\n"
    "\nMeshes the scene's bodies and writes DIR/mesh.vtu; prints node, element and DOF counts.\n";

const char* kInfoHelp =
    "usage: contact2d info SCENE [--set key=value ...]\n"
    "\nMeshes the scene and lists bodies, materials, named edges and node groups with their\n"
    "sizes, and how many nodes each support, load and probe selects.\n";

const char* kTraceHelp =
    "usage: contact2d trace OUTDIR\n"
    "\nDraws from OUTDIR/trace.csv and OUTDIR/contact_steps.csv (written by `run`), as PNG and\n"
    "SVG in OUTDIR:\n"
    "  activation     slave node position x load factor, active nodes coloured by pressure\n"
    "  contact_force  total contact force and active node count against load factor\n"
    "  residuals      Newton residual history of every load step\n";

const char* kCompareHelp =
    "usage: contact2d compare SCENE [--methods a,b,...] [--levels N] [--jobs J]\n"
    "                        [--set key=value ...] [--out DIR] [--quiet]\n"
    "\nRuns every chosen contact method (default: all six) on the same scene, on N meshes:\n"
    "level 0 is the scene's, each further level halves every mesh size (analysis.mesh_scale).\n"
    "Each run is a `contact2d run` in DIR/levelK/METHOD; J of them at a time. Writes:\n"
    "  compare.csv      one row per method and level: DOFs, status, iterations, times, p_max,\n"
    "                   contact length, force, penetration, errors against [reference]\n"
    "  compare.md       a verdict computed from the table, then the table\n"
    "  accuracy_time    accuracy against solve time, one line per method (PNG, SVG)\n"
    "  pressure_profiles  every method's pressure on the finest level (with Hertz's)\n"
    "  penetration      largest penetration per method and level\n"
    "The table is rewritten after every finished run, so an interrupted study keeps its rows.\n";

const char* kSweepHelp =
    "usage: contact2d sweep SCENE --set key=a:b:log:n [--method M] [--accuracy 0.01]\n"
    "                      [--jobs J] [--set key=value ...] [--out DIR] [--quiet]\n"
    "\nRuns SCENE once per value of one key (a:b:log:n, a:b:lin:n or v1,v2,...), e.g.\n"
    "  contact2d sweep examples/hertz_rigid.toml --method penalty \\\n"
    "      --set contact.penalty.k=1e3:1e13:log:11\n"
    "Each run is a `contact2d run` in DIR/caseK; J at a time. Writes:\n"
    "  sweep.csv   value, status, iterations, solve time, p_max and its error, penetration,\n"
    "              force, the factorisation's pivot ratio, penalty, max|K_ij|\n"
    "  sweep.md    the range of values that converge with |p_max error| <= accuracy, and (for\n"
    "              penalty.k) where the seed's rule k = 1e4 max|K_ij| falls; then the table\n"
    "  sweep.png   error, penetration, iterations, time and pivot ratio against the value\n";

const char* kBenchHelp =
    "usage: contact2d bench [--quick] [--out DIR] [--examples DIR] [--quiet]\n"
    "\n"
    "Runs a fixed ladder of the bundled scenes, one `contact2d run` process at a time, and\n"
    "reports speed and accuracy. Full ladder (run by hand; about 15 minutes on 2 cores): linear\n"
    "elasticity (cantilever) and Hertz (rigid flat, elastic block), T3 and T6, at about 10k,\n"
    "100k and 1M DOFs; the two cantilevers (nonlinear contact) at 10k and 100k; every contact\n"
    "method on hertz_rigid_fast and hertz_block_fast, as shipped and refined. --quick: a small\n"
    "ladder in well under a minute (CI). Writes into DIR (default out/bench):\n"
    "  bench.csv          one row per run: DOFs, status, iterations, time per phase (mesh,\n"
    "                     assemble, symbolic and numeric factorisation, triangular solves,\n"
    "                     the rest of the contact solve, detection, recovery, output), total,\n"
    "                     process wall time, peak memory, accuracy, contact overhead\n"
    "  bench.md           the targets with the measured figure beside each, the tables,\n"
    "                     fitted slopes of time against DOFs\n"
    "  time_vs_dofs       log-log, per family and per phase, fitted slopes (PNG, SVG)\n"
    "  accuracy_vs_time   pressure-profile error against time per method (PNG, SVG)\n"
    "  NN_<case>/         each run's own outputs (summary.json, ...)\n"
    "Assembly throughput is measured in process on structured grids. Timings are figures,\n"
    "not pass/fail: the exit code is 1 only when a run crashed or a chart failed.\n";

const char* kCalibrateHelp =
    "usage: contact2d calibrate SCENE --data measured.csv --fit key[,key...] [--method M]\n"
    "                          [--set key=value ...] [--out DIR] [--quiet]\n"
    "\nFits scene parameters so the scene's [[probe]] values match measured ones (Ceres,\n"
    "Levenberg-Marquardt; residuals relative to the measured values, times the weights).\n"
    "  measured.csv   columns probe,value[,weight]; probe names the scene's [[probe]]s\n"
    "  --fit          scene keys as for --set; E, nu, thickness mean material.E, ...; a vector\n"
    "                 component as load[0].total_force[1]; bounds as key=lower:upper[:log|lin]\n"
    "                 (default: the scene value / 100 .. x 100, log scale)\n"
    "Writes calibrate.json and calibrate.md: fitted values with standard deviations from the\n"
    "covariance, residuals, and the solver's summary.\n";

const char* kPlotHelp =
    "usage: contact2d plot OUTDIR [--field F[,F...]|all] [--zoom x0,y0,x1,y1] [--deformed S]\n"
    "                             [--step K | --cycle K] [--edges] [--levels N]\n"
    "\nPictures of a finished run from its VTU files (PNG and SVG, written into OUTDIR):\n"
    "  --field      sx sy sxy vm p1 p2 (smoothed stresses, principal p1 >= p2), ux uy, or\n"
    "               error: elements coloured by the ZZ local parameter, <= 1 and > 1 as the\n"
    "               seed did (default vm); writes plot_<field>.png\n"
    "  --zoom       window in model coordinates; the colour scale spans the nodes inside it\n"
    "  --deformed   draw on the deformed mesh, displacements times S (auto: 8 % of the model)\n"
    "  --step K     load step K (step_000K.vtu; default the last); --cycle K: adaptive cycle K\n"
    "  --edges      draw element edges     --levels N  colour bands (default 12)\n"
    "An adaptive run's folder also gets adapt_meshes.png: up to four cycles' meshes side by\n"
    "side (in the zoom window when given).\n";

struct Options {
  std::string verb, scene;
  std::vector<std::string> sets;
  std::string out, method, methods, data;
  std::vector<std::string> fits;
  int levels = 1, jobs = 1;
  double accuracy = 0.01;
  bool quiet = false, help = false;
  // plot
  std::vector<std::string> fields;
  std::string zoom, deformed;
  int step = 0, cycle = -1, plot_levels = 12;
  bool edges = false;
  // run --adapt: overrides of the [adapt] table
  bool adapt = false;
  std::vector<std::string> adapt_sets;
  // bench
  bool quick = false;
  std::string examples;
};

/// The non-empty items of a comma-separated list ("a,b,,c" -> a, b, c).
std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream list(text);
  for (std::string item; std::getline(list, item, ',');)
    if (!item.empty()) items.push_back(item);
  return items;
}

int parse_count(const std::string& flag, const std::string& text) {
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || v < 1 || v > 1000)
    throw InputError(flag + ": expected a positive integer, found '" + text + "'");
  return static_cast<int>(v);
}

Options parse_args(int argc, char** argv) {
  Options o;
  if (argc < 2) return o;
  o.verb = argv[1];
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const std::string& flag) -> std::string {
      if (i + 1 >= argc) throw InputError(flag + ": expected a value, found the end of the line");
      return argv[++i];
    };
    if (a == "--help" || a == "-h") o.help = true;
    else if (a == "--set") o.sets.push_back(value(a));
    else if (a.rfind("--set=", 0) == 0) o.sets.push_back(a.substr(6));
    else if (a == "--out") o.out = value(a);
    else if (a == "--method") o.method = value(a);
    else if (a == "--methods") o.methods = value(a);
    else if (a == "--data") o.data = value(a);
    else if (a == "--fit") {
      for (auto& f : split_list(value(a))) o.fits.push_back(std::move(f));
    }
    else if (a.rfind("--methods=", 0) == 0) o.methods = a.substr(10);
    else if (a == "--levels") o.levels = parse_count(a, value(a));
    else if (a.rfind("--levels=", 0) == 0) o.levels = parse_count("--levels", a.substr(9));
    else if (a == "--jobs") o.jobs = parse_count(a, value(a));
    else if (a == "--accuracy") {
      const std::string v = value(a);
      char* end = nullptr;
      o.accuracy = std::strtod(v.c_str(), &end);
      if (v.empty() || *end != '\0' || !(o.accuracy > 0 && o.accuracy < 1))
        throw InputError("--accuracy: expected a relative error in (0, 1), found '" + v + "'");
    }
    else if (a.rfind("--jobs=", 0) == 0) o.jobs = parse_count("--jobs", a.substr(7));
    else if (a.rfind("--method=", 0) == 0) o.method = a.substr(9);
    else if (a.rfind("--out=", 0) == 0) o.out = a.substr(6);
    else if (a == "--field") {
      for (auto& f : split_list(value(a))) o.fields.push_back(std::move(f));
    }
    else if (a == "--zoom") o.zoom = value(a);
    else if (a == "--deformed") o.deformed = value(a);
    else if (a == "--step") o.step = parse_count(a, value(a));
    else if (a == "--cycle") {
      const std::string v = value(a);
      o.cycle = v == "0" ? 0 : parse_count(a, v);
    }
    else if (a == "--edges") o.edges = true;
    else if (a == "--quick" && o.verb == "bench") o.quick = true;
    else if (a == "--examples" && o.verb == "bench") o.examples = value(a);
    else if (a == "--levels" && o.verb == "plot") o.plot_levels = parse_count(a, value(a));
    else if (a == "--adapt") {
      // --adapt [target=0.05] [max_cycles=8] [max_shrink=0.2] [max_growth=2]: the [adapt] table.
      o.adapt = true;
      o.adapt_sets.push_back("adapt.enabled=true");
      while (i + 1 < argc) {
        const std::string kv = argv[i + 1];
        const auto eq = kv.find('=');
        const std::string key = kv.substr(0, eq);
        if (eq == std::string::npos ||
            (key != "target" && key != "max_cycles" && key != "max_shrink" && key != "max_growth"))
          break;
        o.adapt_sets.push_back("adapt." + kv);
        ++i;
      }
    }
    else if (a == "--quiet" || a == "-q") o.quiet = true;
    else if (!a.empty() && a[0] == '-') throw InputError(a + ": unknown option (see --help)");
    else if (o.scene.empty()) o.scene = a;
    else throw InputError(a + ": unexpected argument (one scene per run)");
  }
  return o;
}

/// Progress and log: lines go to the terminal (unless quiet) and to run.log.
class Reporter {
 public:
  explicit Reporter(bool quiet) : quiet_(quiet), tty_(::isatty(STDERR_FILENO)) {}
  void phase(const std::string& what) {
    log_ << what << '\n';
    if (!quiet_ && tty_) std::cerr << "  .. " << what << std::endl;
  }
  void line(const std::string& text) {
    log_ << text;
    if (!quiet_) std::cout << text << std::flush;
  }
  std::string log() const { return log_.str(); }

 private:
  bool quiet_, tty_;
  std::ostringstream log_;
};

/// The scene with --set and, for --adapt, the [adapt] overrides applied.
core::Scene load_run_scene(const Options& o) {
  core::Scene scene = core::load_scene(o.scene, o.sets);
  if (o.adapt && scene.explicit_model) {
    scene.adapt.enabled = true;  // --set does not apply to legacy files; solve_adaptive refuses it
  } else if (o.adapt) {
    std::vector<std::string> sets = o.sets;
    sets.insert(sets.end(), o.adapt_sets.begin(), o.adapt_sets.end());
    scene = core::load_scene(o.scene, sets);
  }
  return scene;
}

std::string cycle_line(const app::AdaptCycle& c) {
  char line[200];
  std::snprintf(line, sizeof line,
                "adapt %2d   %8d DOFs   xi_g %8.3g   max xi_e %8.3g   error %6.2f %%   %7.2f s\n",
                c.cycle, c.dofs, c.global_parameter, c.max_local, 100 * c.relative_error,
                c.seconds);
  return line;
}

std::string default_out(const Options& o, const core::Scene& scene) {
  if (!o.out.empty()) return o.out;
  if (!scene.output_dir.empty()) return scene.output_dir;
  return "out/" + fs::path(o.scene).stem().string();
}

int cmd_run(const Options& o) {
  const auto t0 = app::RunOutput::Clock::now();
  Reporter rep(o.quiet);
  rep.phase("reading " + o.scene);
  const core::Scene scene = load_run_scene(o);
  app::RunOutput output(scene, default_out(o, scene));
  const auto phase = [&](const std::string& line) { rep.phase(line); };
  std::unique_ptr<app::SceneRun> solved;
  app::AdaptRun adapt;
  if (scene.adapt.enabled) {
    // Every cycle leaves its mesh and fields and a row of adapt.csv as soon as it is solved.
    adapt = app::solve_adaptive(scene, o.method, phase, [&](const app::AdaptCycle& c, const app::SceneRun& r) {
      output.write_cycle(c, r);
      rep.line(cycle_line(c));
    });
    solved = std::move(adapt.last);
  } else {
    // A load-stepped run leaves every converged step as soon as it is solved.
    solved = app::solve_scene(scene, o.method, phase,
                         [&](const nonlinear::StepRecord& s, const core::Model& m,
                             const core::Results& r) { output.write_step(s, m, r); });
  }
  rep.phase("writing results to " + output.dir());
  const std::string chart_error = output.write_results(*solved, t0);
  const nlohmann::json summary =
      output.write_summary(*solved, scene.adapt.enabled ? &adapt : nullptr);
  rep.line(app::terminal_summary(summary, output.dir()));
  if (scene.adapt.enabled)
    rep.line(std::string(adapt.reached ? "adapt      " : "warning    adapt: ") + adapt.stop +
             " (adapt.csv, cycle_NN.vtu)\n");
  if (!chart_error.empty()) rep.line("warning    chart not written: " + chart_error + "\n");
  output.write_log(rep.log());
  return solved->results.status == SolveStatus::kConverged ? kExitOk : kExitSolveFailed;
}


/// The options every study verb shares.
void fill_study(const Options& o, app::StudyOptions& s) {
  s.scene = o.scene;
  s.method = o.method;
  s.sets = o.sets;
  s.jobs = o.jobs;
  s.out = o.out;
  s.quiet = o.quiet;
}

int cmd_compare(const Options& o) {
  app::CompareOptions c;
  fill_study(o, c);
  c.methods = split_list(o.methods);
  c.levels = o.levels;
  return app::run_compare(c);
}

int cmd_sweep(const Options& o) {
  app::SweepOptions w;
  fill_study(o, w);
  w.accuracy = o.accuracy;
  return app::run_sweep(w);
}

int cmd_calibrate(const Options& o) {
  app::CalibrateOptions c;
  fill_study(o, c);
  c.data = o.data;
  c.fits = o.fits;
  return app::run_calibrate(c);
}

/// What a chart verb wrote into DIR (stem, what it shows), then its error if any: the exit code.
int report_charts(const std::string& dir,
                  const std::vector<std::pair<std::string, std::string>>& written,
                  const std::string& error) {
  for (const auto& [stem, what] : written)
    std::cout << "wrote " << dir << "/" << stem << ".png and .svg: " << what << "\n";
  if (!error.empty()) {
    std::cerr << "error: " << error << "\n";
    return kExitSolveFailed;
  }
  return kExitOk;
}

int cmd_trace(const Options& o) {
  const app::TraceCharts charts = app::draw_trace_charts(o.scene);
  return report_charts(o.scene, charts.written, charts.error);
}

int cmd_plot(const Options& o) {
  app::PlotRequest req;
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
      throw InputError("--zoom: expected x0,y0,x1,y1 with x1 > x0 and y1 > y0, found '" + o.zoom + "'");
    req.options.zoom = z;
  }
  if (!o.deformed.empty()) {
    char* end = nullptr;
    req.options.deformed = o.deformed == "auto" ? -1.0 : std::strtod(o.deformed.c_str(), &end);
    if (o.deformed != "auto" && (*end != '\0' || !(req.options.deformed > 0)))
      throw InputError("--deformed: expected a positive scale or auto, found '" + o.deformed + "'");
  }
  const app::PlotWritten w = app::plot_run(req);
  return report_charts(o.scene, w.written, w.error);
}

int cmd_mesh(const Options& o) {
  const core::Scene scene = core::load_scene(o.scene, o.sets);
  const core::Model model = core::build_model(scene);
  const std::string out = default_out(o, scene);
  fs::create_directories(out);
  const core::Results empty = core::Results::zeros(
      model.mesh.num_nodes(), model.mesh.num_elements(), model.mesh.nodes_per_element());
  core::write_file_atomic(out + "/mesh.vtu", core::vtu_document(model, empty));
  const auto [hmin, hmax] = model.mesh.edge_length_range();
  std::cout << (model.mesh.order == 1 ? "T3" : "T6") << " mesh: " << model.mesh.num_nodes()
            << " nodes, " << model.mesh.num_elements() << " elements, " << model.mesh.num_dofs()
            << " DOFs (" << model.dofs.num_free() << " free), edge length " << hmin << " .. "
            << hmax << ", " << model.mesh_seconds << " s\n";
  const auto [min_angle, skinny] = model.mesh.angle_quality();
  std::cout << "quality    smallest angle " << min_angle << " deg";
  if (skinny > 0)
    std::cout << "; warning: " << skinny << " skinny triangle" << (skinny == 1 ? "" : "s")
              << " (an angle below 15 deg)";
  std::cout << "\nwrote " << out << "/mesh.vtu\n";
  return kExitOk;
}

int cmd_info(const Options& o) {
  const core::Scene scene = core::load_scene(o.scene, o.sets);
  const core::Model model = core::build_model(scene);
  std::cout << "scene      " << scene.path << (scene.title.empty() ? "" : " - " + scene.title)
            << "\nunits      " << (scene.units.empty() ? "(not stated)" : scene.units)
            << "\nanalysis   "
            << (scene.analysis.state == core::PlaneState::kPlaneStrain ? "plane strain"
                                                                       : "plane stress")
            << ", " << (model.mesh.order == 1 ? "T3" : "T6") << "\nmesh       "
            << model.mesh.num_nodes() << " nodes, " << model.mesh.num_elements() << " elements, "
            << model.dofs.num_free() << " free DOFs of " << model.mesh.num_dofs() << "\n";
  for (const auto& m : model.materials)
    std::cout << "material   " << m.name << ": E = " << m.young << ", nu = " << m.poisson
              << ", t = " << m.thickness << "\n";
  for (size_t b = 0; b < model.body_names.size(); ++b) {
    int elements = 0;
    for (int id : model.mesh.element_body) elements += id == static_cast<int>(b);
    std::cout << "body       " << model.body_names[b] << ": " << elements << " elements\n";
  }
  for (const auto& [name, ids] : model.mesh.edge_groups)
    std::cout << "edge set   " << name << ": " << ids.size() << " edges\n";
  for (const auto& [name, ids] : model.mesh.node_groups)
    std::cout << "node set   " << name << ": " << ids.size() << " nodes\n";
  for (const auto& s : scene.supports)
    std::cout << "support    " << s.at.where << ": " << core::select_nodes(model, s.on).size()
              << " nodes\n";
  for (const auto& l : scene.loads)
    std::cout << "load       " << l.at.where << ": " << core::select_nodes(model, l.on).size()
              << " nodes\n";
  for (const auto& p : scene.probes)
    std::cout << "probe      " << p.name << " (" << p.quantity << ")"
              << (p.on ? ": " + std::to_string(core::select_nodes(model, *p.on).size()) + " nodes"
                       : std::string(""))
              << "\n";
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse_args(argc, argv);
    if (o.verb.empty() || o.verb == "--help" || o.verb == "-h" || o.verb == "help") {
      std::cout << kMainHelp;
      return o.verb.empty() ? kExitBadInput : kExitOk;
    }
    const char* help = o.verb == "run"    ? kRunHelp
                       : o.verb == "mesh" ? kMeshHelp
                       : o.verb == "info" ? kInfoHelp
                       : o.verb == "trace" ? kTraceHelp
                       : o.verb == "plot" ? kPlotHelp
                       : o.verb == "compare" ? kCompareHelp
                       : o.verb == "sweep" ? kSweepHelp
                       : o.verb == "calibrate" ? kCalibrateHelp
                       : o.verb == "bench" ? kBenchHelp
                                          : nullptr;
    if (!help)
      throw InputError(o.verb +
                       ": unknown verb; expected run, mesh, info, compare, sweep, calibrate, bench, trace or plot "
                       "(see --help)");
    if (o.help) {
      std::cout << help;
      return kExitOk;
    }
    if (o.verb == "bench") {
      if (!o.scene.empty()) throw InputError(o.scene + ": unexpected argument (bench takes no scene)");
      app::BenchOptions b;
      b.quick = o.quick;
      b.out = o.out;
      b.examples = o.examples.empty() ? C2D_EXAMPLES_DIR : o.examples;
      b.quiet = o.quiet;
      return app::run_bench(b);
    }
    if (o.scene.empty())
      throw InputError(o.verb + ": expected " +
                       (o.verb == "trace" || o.verb == "plot" ? "an output folder" : "a scene file") + ", found none");
    if (o.verb == "run") return cmd_run(o);
    if (o.verb == "trace") return cmd_trace(o);
    if (o.verb == "plot") return cmd_plot(o);
    if (o.verb == "compare") return cmd_compare(o);
    if (o.verb == "sweep") return cmd_sweep(o);
    if (o.verb == "calibrate") return cmd_calibrate(o);
    if (o.verb == "mesh") return cmd_mesh(o);
    return cmd_info(o);
  } catch (const InputError& e) {
    std::cerr << "error: " << e.what() << '\n';
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << '\n';
    return kExitSolveFailed;
  }
}
