#include "app/cli/help.hpp"

#include "constraints/method_registry.hpp"

namespace c2d::app {

namespace {

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
    "  merge DIR      a compare, sweep or bench study's table, verdict and charts from the\n"
    "                 case folders that have finished, wherever they ran; lists missing cases\n"
    "\n"
    "compare, sweep and bench --job-list write their cases as a job list (DIR/jobs.txt, one\n"
    "`contact2d run` per line; DIR/slurm.sh, an sbatch array; DIR/study.json) instead of\n"
    "running them: run it with GNU parallel or Slurm, then `contact2d merge DIR`.\n"
    "\n"
    "Every verb has --help. Exit codes: 0 ok, 1 solve failed (partial results kept),\n"
    "2 bad input, 3 the output could not be written (a full disk), 130 interrupted.\n";

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
    "  contact.csv    gap, force and recovered pressure per slave node (contact scenes); with\n"
    "                 friction also tangential force, shear, slip, accumulated slip, state\n"
    "  constraints.csv  per [[constraint]] row: its constraint, multiplier (force), residual\n"
    "  trace.csv      one row per Newton / active-set iteration of every load step: residual,\n"
    "                 active set, entering, leaving, penetration, pressure, status, stick, slip\n"
    "  contact_steps.csv  per load step and slave node: gap, force, pressure, active (and the\n"
    "                 friction columns of contact.csv)\n"
    "  adapt.csv      adaptive runs: per cycle DOFs, xi_g, max xi_e, error, time, probes;\n"
    "                 cycle_NN.vtu (listed in adapt.pvd) holds each cycle's mesh and fields\n"
    "\n"
    "  --method M       contact enforcement, overriding the scene's [[contact]] method:\n"
    "@METHODS@"
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
    "  residuals      Newton residual history of every load step\n"
    "  stick_slip     (friction) slave node position x load factor: open, stick, slip\n"
    "  stick_slip_counts  (friction) sticking and slipping nodes against load factor\n";

const char* kCompareHelp =
    "usage: contact2d compare SCENE [--methods a,b,...] [--levels N] [--jobs J]\n"
    "                        [--metric KEY] [--set key=value ...] [--out DIR] [--quiet]\n"
    "                        [--job-list] [--case-timeout S]\n"
    "\nRuns every chosen contact method (default: all six) on the same scene, on N meshes:\n"
    "level 0 is the scene's, each further level halves every mesh size (analysis.mesh_scale).\n"
    "Each run is a `contact2d run` in DIR/levelK/METHOD; J of them at a time (J > 1: then\n"
    "each runs once more alone, without charts or fields, for the table's times). Writes:\n"
    "  compare.csv      one row per method and level: DOFs, status, iterations, times, p_max,\n"
    "                   contact length, force, penetration, errors against [reference]\n"
    "  compare.md       a verdict computed from the table, then the table\n"
    "The verdict judges by --metric KEY (a reference error such as pressure_profile_l2 or\n"
    "p_max, or a contact figure or probe measured against lagrange on the finest level;\n"
    "default: the scene's reference) and does not rank a method whose observed order is\n"
    "negative, near zero or erratic. On Hertz, pressure_profile_l2 (over |x| <= 1.5 b) is\n"
    "ruled by the contact edge, at best first order with a wobble set by where b falls\n"
    "between nodes; --metric inner (pressure_profile_inner_l2, |x| <= 0.9 b) and\n"
    "contact_length separate the smooth pressure from the edge's position.\n"
    "  accuracy_time    accuracy against solve time, one line per method (PNG, SVG)\n"
    "  pressure_profiles  every method's pressure on the finest level (with Hertz's)\n"
    "  penetration      largest penetration per method and level\n"
    "The table is rewritten after every finished run, so an interrupted study keeps its rows.\n"
    "@JOBLIST@";

const char* kSweepHelp =
    "usage: contact2d sweep SCENE --set key=a:b:log:n [--method M] [--accuracy 0.01]\n"
    "                      [--metric KEY] [--jobs J] [--set key=value ...] [--out DIR]\n"
    "                      [--quiet] [--job-list] [--case-timeout S]\n"
    "\nRuns SCENE once per value of one key (a:b:log:n, a:b:lin:n or v1,v2,...), e.g.\n"
    "  contact2d sweep examples/hertz_rigid.toml --method penalty \\\n"
    "      --set contact.penalty.k=1e3:1e13:log:11\n"
    "The swept --set is the one whose value is such a range or list of numbers; every other\n"
    "--set is applied to each run as given (a title \"Hertz, fine\" included).\n"
    "Each run is a `contact2d run` in DIR/caseK; J at a time (J > 1: then each runs once\n"
    "more alone, without charts or fields, for the table's times). Writes:\n"
    "  sweep.csv   value, status, iterations, solve time, p_max and its error, penetration,\n"
    "              force, the factorisation's pivot ratio, penalty, max|K_ij|\n"
    "  sweep.md    the range of values that converge with |p_max error| <= accuracy, and (for\n"
    "              penalty.k) where the seed's rule k = 1e4 max|K_ij| falls; then the table\n"
    "  sweep.png   error, penetration, iterations, time and pivot ratio against the value\n"
    "Judged by --metric KEY (default p_max). A penalty or augmentation key also runs lagrange\n"
    "on the same mesh once (DIR/baseline): the verdict gives the values within the accuracy of\n"
    "it, and the chart draws it, so the penalty is not blamed for the mesh's error.\n"
    "@JOBLIST@";

const char* kBenchHelp =
    "usage: contact2d bench [--quick] [--out DIR] [--examples DIR] [--quiet] [--job-list]\n"
    "                      [--case-timeout S]\n"
    "\n"
    "Runs a fixed ladder of the bundled scenes, one `contact2d run` process at a time, and\n"
    "reports speed and accuracy. Full ladder (run by hand; about 15 minutes on 2 cores): linear\n"
    "elasticity (cantilever) and Hertz (rigid flat, elastic block; lagrange and ssn), T3 and\n"
    "T6, at about 10k, 100k and 1M DOFs; the two cantilevers (nonlinear contact) at 10k and\n"
    "100k; every contact method on hertz_rigid_fast and hertz_block_fast, as shipped and\n"
    "refined. --quick: a small\n"
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
    "not pass/fail: the exit code is 1 only when a run crashed or timed out or a chart failed.\n"
    "@JOBLIST@";

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

// Every study's help ends with this and the job list's paragraph in place of @JOBLIST@.
const char* kCaseTimeoutHelp =
    "  --case-timeout S  stop a case still running after S seconds (default 1800; 0: no\n"
    "              limit): SIGTERM to its processes, SIGKILL 5 s later. Its row says\n"
    "              `timeout`, the report lists it with the limit, the study goes on with the\n"
    "              other cases and exits 1. The default is about 90 times the bench's longest\n"
    "              case (a 1.2M-DOF Hertz run, about 20 s on 2 cores): room for a slower\n"
    "              machine or a larger scene, and still an end to a case that never ends.\n"
    "              In slurm.sh it becomes each task's --time; for parallel, add --timeout S.\n";

const char* kJobListHelp =
    "Every study also writes DIR/jobs.txt, DIR/slurm.sh and DIR/study.json (below).\n"
    "  --job-list  write them and stop, instead of running the cases: jobs.txt holds one\n"
    "              `contact2d run` command line per case (absolute paths of the program and\n"
    "              the scene, every argument single-quoted; BLAS/OpenMP threads 1 unless set),\n"
    "              to be run from DIR, each writing its case folder inside DIR:\n"
    "                cd DIR && parallel -j 4 < jobs.txt       (GNU parallel)\n"
    "                cd DIR && sbatch slurm.sh                (Slurm: task K runs line K)\n"
    "              then `contact2d merge DIR` writes the report from the finished cases.\n"
    "              DIR must not hold the case folders yet.\n"
    "slurm.sh asks the cluster, per task (one case), with these #SBATCH lines:\n"
    "  --slurm-partition P     --partition=P (default: none, the cluster's default partition)\n"
    "  --slurm-time T          --time=T, Slurm's format (minutes, H:M:S, D-H:M:S; default: the\n"
    "                          --case-timeout rounded up to minutes, one more to start)\n"
    "  --slurm-mem M           --mem=M (default 4G: the bench's largest case peaks at 3.4 GB)\n"
    "  --slurm-cpus-per-task K --cpus-per-task=K (default 1), also the case's BLAS and OpenMP\n"
    "                          threads\n";

const char* kMergeHelp =
    "usage: contact2d merge DIR [--quiet]\n"
    "\nWrites the report of the compare, sweep or bench study in DIR (its tables, verdict and\n"
    "charts, as the study itself would) from every case folder that holds a summary.json,\n"
    "wherever and whenever it ran. DIR/study.json (written by the study, with or without\n"
    "--job-list) names the study, its options and its cases; nothing else is needed, not even\n"
    "the scene. Cases without a summary.json (not run, running, crashed) are listed on the\n"
    "terminal and in the markdown with their line in jobs.txt, so they can be run again\n"
    "(sed -n '3p;7p' jobs.txt | parallel, or sbatch --array=3,7 slurm.sh).\n"
    "Process wall time and peak memory are not known to a merge (their columns are empty).\n"
    "Exit codes: 0 every case finished, 1 some are missing (or a chart failed), 2 DIR holds no\n"
    "study.json or a malformed one.\n";

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

}  // namespace

const char* main_help() { return kMainHelp; }

/// The run verb's text with the method registry's entries in place of @METHODS@.
const char* run_help() {
  static const std::string text = [] {
    std::string methods;
    for (const auto& m : constraints::method_registry())
      methods += "                   " + m.name + std::string(m.name.size() < 17 ? 17 - m.name.size() : 1, ' ') +
                 (m.exact ? "exact: " : "regularised: ") + m.summary + "\n";
    std::string t = kRunHelp;
    t.replace(t.find("@METHODS@"), 9, methods);
    return t;
  }();
  return text.c_str();
}

/// A study verb's text with the job-list paragraph in place of @JOBLIST@.
std::string with_job_list(const char* text) {
  std::string t = text;
  t.replace(t.find("@JOBLIST@"), 9, std::string(kCaseTimeoutHelp) + kJobListHelp);
  return t;
}

/// compare's, sweep's or bench's text.
const char* study_help(const std::string& verb) {
  static const std::string compare = with_job_list(kCompareHelp), sweep = with_job_list(kSweepHelp),
                           bench = with_job_list(kBenchHelp);
  return (verb == "compare" ? compare : verb == "sweep" ? sweep : bench).c_str();
}

const char* verb_help(const std::string& verb) {
  return verb == "run"         ? run_help()
         : verb == "mesh"      ? kMeshHelp
         : verb == "info"      ? kInfoHelp
         : verb == "trace"     ? kTraceHelp
         : verb == "plot"      ? kPlotHelp
         : verb == "compare"   ? study_help(verb)
         : verb == "sweep"     ? study_help(verb)
         : verb == "calibrate" ? kCalibrateHelp
         : verb == "bench"     ? study_help(verb)
         : verb == "merge"     ? kMergeHelp
                               : nullptr;
}

}  // namespace c2d::app
