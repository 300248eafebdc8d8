// End to end through the executable: exit codes, summary.json, VTU consistency.
#include <gtest/gtest.h>

#include "app/report/charts.hpp"
#include "app/report/summary.hpp"
#include "app/report/units.hpp"
#include "app/report/field_plot.hpp"
#include "app/process.hpp"
#include "app/studies/study.hpp"
#include "app/studies/sweep.hpp"
#include "app/report/hertz.hpp"
#include "app/report/csv_table.hpp"
#include "constraints/method_registry.hpp"
#include "read_text.hpp"

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <sstream>
#include <thread>
#include <tuple>
#include <vector>

namespace fs = std::filesystem;
using c2d::test::read_text;

namespace {

/// Runs the executable with ARGS (split at spaces; no shell) and returns its exit code.
int run_args(const std::vector<std::string>& args, std::string* output = nullptr) {
  // One log per process: CTest runs the tests of this file in parallel processes.
  const fs::path log =
      fs::temp_directory_path() / ("c2d_cli_test_" + std::to_string(::getpid()) + ".log");
  const c2d::app::ProcessOutcome p = c2d::app::run_process(C2D_BINARY, args, log.string());
  if (output) {
    *output = read_text(log);
  }
  return p.started ? p.exit_code : -1;
}

int run(const std::string& args, std::string* output = nullptr) {
  std::vector<std::string> words;
  std::istringstream in(args);
  for (std::string w; in >> w;) words.push_back(w);
  return run_args(words, output);
}

std::string example(const char* name) { return std::string(C2D_SOURCE_DIR) + "/examples/" + name; }

/// A chart written as DIR/STEM.png (PNG signature) and DIR/STEM.svg (an <svg> document).
void expect_chart(const fs::path& dir, const std::string& stem) {
  std::ifstream png(dir / (stem + ".png"), std::ios::binary);
  char sig[8] = {};
  png.read(sig, 8);
  EXPECT_EQ(std::string(sig + 1, 3), "PNG") << stem;
  const std::string text = read_text(dir / (stem + ".svg"));
  EXPECT_NE(text.find("<svg"), std::string::npos) << stem;
}

}  // namespace

TEST(Cli, CantileverRunWritesSummaryAndValidVtu) {
  const fs::path out = fs::temp_directory_path() / "c2d_cli_cantilever";
  fs::remove_all(out);
  ASSERT_EQ(run("run " + example("cantilever.toml") + " --out " + out.string() + " --quiet"), 0);
  std::ifstream in(out / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(s["status"], "converged");
  const double tip = s["probes"]["tip_uy"];
  EXPECT_NEAR(tip, -0.012208, 0.005 * 0.012208);
  EXPECT_NEAR(s["probes"]["reaction_y"].get<double>(), 3.0, 1e-9);  // equilibrium
  for (const char* key : {"mesh", "time_s", "error", "probes", "steps", "newton_iterations"})
    EXPECT_TRUE(s.contains(key)) << key;
  // VTU: the counts in the header match the arrays.
  const std::string doc = read_text(out / "step_0001.vtu");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(doc, m, std::regex("NumberOfPoints=\"(\\d+)\" NumberOfCells=\"(\\d+)\"")));
  EXPECT_EQ(std::stoi(m[1]), s["mesh"]["nodes"].get<int>());
  EXPECT_EQ(std::stoi(m[2]), s["mesh"]["elements"].get<int>());
  EXPECT_NE(doc.find("</VTKFile>"), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "results.pvd"));
  EXPECT_TRUE(fs::exists(out / "nodes.csv"));
  EXPECT_TRUE(fs::exists(out / "deformed.png"));
}

TEST(Cli, LargeRunFactorisesSplitAndSaysSo) {
  // From 40,000 free DOFs the stiffness factorises as two halves and the separator
  // (core/split_cholesky.hpp): the cantilever at 47k DOFs (T6), tip against Timoshenko (0.5 %).
  const fs::path out = fs::temp_directory_path() / "c2d_cli_split";
  fs::remove_all(out);
  ASSERT_EQ(run_args({"run", example("cantilever.toml"), "--set", "analysis.mesh_scale=0.28",
                      "--set", "output.charts=false", "--out", out.string(), "--quiet"}),
            0);
  std::ifstream in(out / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(s["status"], "converged");
  EXPECT_GT(s["mesh"]["nodes"].get<int>() * 2, 40000);
  EXPECT_EQ(s["solver"]["ordering"], "corner_amd_split");
  EXPECT_GT(s["solver"]["separator"].get<int>(), 0);
  EXPECT_LT(s["solver"]["relative_residual"].get<double>(), 1e-8);
  EXPECT_NEAR(s["probes"]["tip_uy"].get<double>(), -0.012208, 0.005 * 0.012208);
}

TEST(Cli, BadInputExitsTwoWithOneLine) {
  std::string output;
  EXPECT_EQ(run("run " + example("cantilever.toml") + " --set analysis.element=Q8 --quiet", &output), 2);
  EXPECT_NE(output.find("analysis.element"), std::string::npos) << output;
  EXPECT_EQ(run("run /nonexistent.toml", &output), 2);
  EXPECT_NE(output.find("/nonexistent.toml"), std::string::npos);
  EXPECT_EQ(run("frobnicate x", &output), 2);
}

TEST(Cli, UnsupportedBodyFailsWithExitOneAndKeepsSummary) {
  // No support at all: the stiffness is singular; status says so, exit 1, summary written.
  const fs::path out = fs::temp_directory_path() / "c2d_cli_singular";
  fs::remove_all(out);
  EXPECT_EQ(run_args({"run", example("cantilever.toml"), "--set", "support[0].on.edge=bottom",
                      "--set", "support[0].fix=[\"uy\"]", "--out", out.string(), "--quiet"}),
            1);
  std::ifstream in(out / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_NE(s["status"].get<std::string>().find("failed: singular"), std::string::npos) << s["status"];
}

// info lists each support, load and plate with its amplitude's points (the stages a run takes):
// the Cattaneo–Mindlin example's normal then tangential load, and a support staged by --set.
TEST(Cli, InfoListsTheStagesOfLoadsSupportsAndPlates) {
  std::string output;
  ASSERT_EQ(run_args({"info", example("cattaneo_mindlin.toml"), "--set",
                      "support[0].amplitude=[[0.0, 0.0], [1.0, 2.0]]"},
                     &output),
            0)
      << output;
  EXPECT_NE(output.find("support[0]: 27 nodes, staged: a = 0 at λ 0, 2 at λ 1"), std::string::npos)
      << output;
  EXPECT_NE(output.find("load[0]): 53 nodes, staged: a = 0 at λ 0, 1 at λ 0.5, 1 at λ 1"),
            std::string::npos)
      << output;
  EXPECT_NE(output.find("load[1]): 53 nodes, staged: a = 0 at λ 0, 0 at λ 0.5, 1 at λ 1"),
            std::string::npos)
      << output;
  EXPECT_NE(output.find("plate      cap ("), std::string::npos) << output;
}

TEST(Cli, HelpForEveryVerb) {
  for (const char* verb : {"run", "mesh", "info", "trace"}) {
    std::string output;
    EXPECT_EQ(run(std::string(verb) + " --help", &output), 0);
    EXPECT_NE(output.find("usage: contact2d"), std::string::npos);
  }
}

TEST(Cli, ContactRunReportsContactAndWritesItsFiles) {
  // The seed's two cantilevers (example 4.3, T6): the upper tip deflects 0.0077 m (seed T6 and
  // SAP2000); 2% tolerance for the reconstructed geometry and mesh.
  const fs::path out = fs::temp_directory_path() / "c2d_cli_cantilevers";
  fs::remove_all(out);
  ASSERT_EQ(run("run " + example("two_cantilevers.toml") + " --method ssn --out " + out.string() +
                " --quiet"),
            0);
  std::ifstream in(out / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(s["status"], "converged");
  EXPECT_EQ(s["method"], "ssn");
  // The method's factorisation, named in the solver section.
  EXPECT_FALSE(s["solver"]["ordering"].get<std::string>().empty());
  EXPECT_GT(s["solver"]["factor_nonzeros"].get<double>(), 0.0);
  EXPECT_GT(s["solver"]["pivot_ratio"].get<double>(), 0.0);
  for (const char* key : {"active_nodes", "p_max", "length", "max_penetration", "total_force"})
    EXPECT_TRUE(s["contact"].contains(key)) << key;
  EXPECT_NEAR(s["probes"]["a_uy"].get<double>(), -0.0077, 0.02 * 0.0077);
  EXPECT_NEAR(s["probes"]["d_uy"].get<double>(), -0.0034, 0.02 * 0.0034);
  // Equilibrium of the lower beam: the contact force equals its support reaction; Euler-Bernoulli
  // compatibility gives 1.11 t.
  EXPECT_NEAR(s["contact"]["total_force"].get<double>(), 1.11, 0.03 * 1.11);
  std::ifstream csv(out / "contact.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "node,x,y,gap,force,pressure,active,penalty");
  // Five load steps (the scene's); contact closes at the third (λ = 0.6, after the
  // Euler-Bernoulli closing load λ_c = 0.41), so the trace's active count rises from 0 to >= 1.
  EXPECT_EQ(s["steps"].get<int>(), 5);
  std::ifstream trace(out / "trace.csv");
  std::string line;
  std::getline(trace, line);
  EXPECT_EQ(line,
            "step,load_factor,attempt,outer,iteration,residual,increment_norm,active,entering,"
            "leaving,max_penetration,max_pressure,penalty,status,stick,slip,factorizations");
  std::map<int, int> active_at_step;
  while (std::getline(trace, line)) {
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    ASSERT_GE(cells.size(), 16u) << line;  // (factorizations: on an outer iteration's last row)
    if (cells[13] == "converged") active_at_step[std::stoi(cells[0])] = std::stoi(cells[7]);
  }
  EXPECT_EQ(active_at_step[1], 0);
  EXPECT_EQ(active_at_step[2], 0);
  EXPECT_GE(active_at_step[3], 1);
  EXPECT_GE(active_at_step[5], 1);
  EXPECT_TRUE(fs::exists(out / "contact_steps.csv"));
  // steps.csv: one row per converged step with the contact's total and the probes; no contact
  // force before closure (λ_c = 0.41), and the last row's equals summary.json's.
  std::ifstream steps_csv(out / "steps.csv");
  std::getline(steps_csv, line);
  EXPECT_EQ(line.rfind("step,load_factor,newton_iterations,factorizations,reaction_x,reaction_y,"
                       "contact_active_nodes,contact_normal_force,contact_tangential_force,",
                       0),
            0u)
      << line;
  std::vector<std::vector<std::string>> step_rows;
  while (std::getline(steps_csv, line)) {
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    step_rows.push_back(cells);
  }
  ASSERT_EQ(step_rows.size(), 5u);
  EXPECT_DOUBLE_EQ(std::stod(step_rows[1][7]), 0.0);
  EXPECT_NEAR(std::stod(step_rows[4][7]), s["contact"]["total_force"].get<double>(),
              1e-9 * s["contact"]["total_force"].get<double>());
  EXPECT_NEAR(std::stod(step_rows[4][1]), 1.0, 1e-12);
  // The trace verb draws the activation, force and residual charts as PNG and SVG.
  std::string output;
  ASSERT_EQ(run("trace " + out.string(), &output), 0) << output;
  for (const char* stem : {"activation", "contact_force", "residuals"}) expect_chart(out, stem);
  const std::string ss = read_text(out / "step_0001.vtu");
  EXPECT_NE(ss.find("Name=\"contact_pressure\""), std::string::npos);
}

TEST(Cli, OutputPathsWithShellAndGnuplotSyntaxRunNothing) {
  // Issue 16, finding 1: an output folder (from --out, [output] dir or the trace verb) named
  // with shell quoting, backquotes, $() or a leading '|' (gnuplot's pipe) must be only a
  // folder name: the runs write their charts into it and nothing else appears.
  const fs::path here = fs::temp_directory_path() / ("c2d_cli_inject_" + std::to_string(::getpid()));
  fs::remove_all(here);
  fs::create_directories(here);
  const fs::path cwd = fs::current_path();
  fs::current_path(here);  // a relative payload would act here
  const std::vector<std::string> payloads = {
      "x';touch PWNED1;'", "y`touch PWNED2`", "z$(touch PWNED3)\"'", "|touch PWNED4"};
  for (const auto& out : payloads) {
    std::string output;
    EXPECT_EQ(run_args({"run", example("hertz_rigid_fast.toml"), "--out", out, "--quiet"}, &output), 0)
        << output;
    expect_chart(here / out, "pressure");
    EXPECT_EQ(run_args({"trace", out}, &output), 0) << output;
  }
  // The same through a scene's [output] dir.
  std::ifstream scene_in(example("hertz_rigid_fast.toml"));
  std::stringstream scene;
  scene << scene_in.rdbuf() << "\n[output]\ndir = \"w';touch PWNED5;'\"\n";
  std::ofstream(here / "scene.toml") << scene.str();
  std::string output;
  EXPECT_EQ(run_args({"run", (here / "scene.toml").string(), "--quiet"}, &output), 0) << output;
  expect_chart(here / "w';touch PWNED5;'", "pressure");
  fs::current_path(cwd);
  std::vector<std::string> created;
  for (const auto& e : fs::recursive_directory_iterator(here))
    if (e.path().filename().string().rfind("PWNED", 0) == 0) created.push_back(e.path().string());
  EXPECT_TRUE(created.empty()) << created.front();
  fs::remove_all(here);
}

TEST(Cli, TraceNamesWhatIsMissing) {
  std::string output;
  EXPECT_EQ(run("trace /nonexistent/c2d_run", &output), 2);
  EXPECT_NE(output.find("/nonexistent/c2d_run: expected the output folder of a run"),
            std::string::npos)
      << output;
  const fs::path dir = fs::temp_directory_path() / "c2d_cli_bad_trace";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "trace.csv") << "step,load_factor,attempt,outer,iteration,residual\n1,0.5,0,1\n";
  EXPECT_EQ(run("trace " + dir.string(), &output), 2);
  EXPECT_NE(output.find("trace.csv:2: expected 6 cells, found 4"), std::string::npos) << output;
}

TEST(Cli, ContactMethodErrorsAndIllConditionedPenalty) {
  std::string output;
  EXPECT_EQ(run("run " + example("two_cantilevers.toml") + " --method newton", &output), 2);
  EXPECT_NE(output.find("found 'newton'"), std::string::npos) << output;
  EXPECT_EQ(run("run " + example("cantilever.toml") + " --method ssn", &output), 2);
  EXPECT_NE(output.find("no [[contact]]"), std::string::npos) << output;
  // k = 1e20 is 1e14 times the elements' stiffness: reported, not solved into garbage.
  const fs::path out = fs::temp_directory_path() / "c2d_cli_k1e20";
  fs::remove_all(out);
  EXPECT_EQ(run("run " + example("two_cantilevers.toml") +
                    " --method penalty --set contact.penalty.k=1e20 --quiet --out " + out.string(),
                &output),
            1);
  std::ifstream in(out / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(s["status"].get<std::string>().rfind("failed: ill_conditioned", 0), 0u) << s["status"];
}

TEST(Cli, NonlinearRunsAndAnImpossibleLoadExitsOneWithItsSteps) {
  // The elastica (P L²/EI = 2): Mattiasson's w/L = 0.49346, u/L = 0.16064 within 0.5 %.
  const fs::path out = fs::temp_directory_path() / "c2d_cli_elastica";
  fs::remove_all(out);
  ASSERT_EQ(run("run " + example("elastica.toml") + " --quiet --out " + out.string()), 0);
  std::ifstream in(out / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_NEAR(-s["probes"]["tip_uy"].get<double>() / 1000.0 / 0.49346, 1.0, 0.005);
  EXPECT_NEAR(-s["probes"]["tip_ux"].get<double>() / 1000.0 / 0.16064, 1.0, 0.005);
  EXPECT_EQ(s["steps"].get<int>(), 10);
  EXPECT_GE(s["newton_iterations"].get<int>(), 10);
  EXPECT_TRUE(fs::exists(out / "trace.csv"));
  // Every converged step leaves its VTU, listed in results.pvd at its load factor; plot draws
  // any of them.
  for (int k = 1; k <= 10; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "step_%04d.vtu", k);
    EXPECT_TRUE(fs::exists(out / name)) << name;
  }
  {
    const std::string t = read_text(out / "results.pvd");
    const std::regex dataset("<DataSet timestep=\"([^\"]+)\"");
    std::vector<double> times;
    for (auto it = std::sregex_iterator(t.begin(), t.end(), dataset); it != std::sregex_iterator(); ++it)
      times.push_back(std::stod((*it)[1]));
    ASSERT_EQ(times.size(), 10u) << t;
    EXPECT_NEAR(times.front(), 0.1, 1e-12);
    EXPECT_NEAR(times.back(), 1.0, 1e-12);
  }
  std::string plot_output;
  ASSERT_EQ(run("plot " + out.string() + " --step 5 --field uy --deformed 1", &plot_output), 0)
      << plot_output;
  expect_chart(out, "plot_uy_step0005");
  // A block pressed with 0.5 E, beyond what St. Venant–Kirchhoff can carry (its nominal stress
  // peaks at E / (3√3)): exit 1, the converged steps kept.
  const fs::path crush = fs::temp_directory_path() / "c2d_cli_crush";
  fs::remove_all(crush);
  fs::create_directories(crush);
  const fs::path scene = fs::temp_directory_path() / "c2d_cli_crush.toml";  // not inside --out
  std::ofstream(scene) << "[analysis]\ngeometric_nonlinearity = true\nsteps = 10\n"
                          "[[material]]\nname = \"m\"\nE = 1000.0\nnu = 0.0\n"
                          "[[body]]\nname = \"b\"\nmaterial = \"m\"\n"
                          "shape = { type = \"rectangle\", min = [0.0, 0.0], max = [1.0, 1.0] }\n"
                          "mesh = { size = 0.5 }\n"
                          "[[support]]\non = { edge = \"bottom\" }\nfix = [\"uy\"]\n"
                          "[[support]]\non = { edge = \"left\" }\nfix = [\"ux\"]\n"
                          "[[load]]\non = { edge = \"top\" }\ntraction = [0.0, -500.0]\n";
  std::string output;
  EXPECT_EQ(run("run " + scene.string() + " --quiet --out " + crush.string(), &output), 1) << output;
  std::ifstream in2(crush / "summary.json");
  const nlohmann::json f = nlohmann::json::parse(in2);
  EXPECT_EQ(f["status"].get<std::string>().rfind("failed: ", 0), 0u) << f["status"];
  EXPECT_GE(f["steps"].get<int>(), 1);
  EXPECT_LT(f["load_factor"].get<double>(), 1.0);
  EXPECT_TRUE(fs::exists(crush / "step_0001.vtu"));
}

TEST(Cli, CompareMortarHertzProfileErrorFallsAtLeastAsFastAsH) {
  // Mortar T6 on a small Hertz cylinder over four levels (3,080 to 164,818 DOFs): the profile's
  // relative L2 error falls with h, and compare reports the order in orders.csv. The contact
  // edge's position among the nodes makes single levels jitter by ±40 % (at level 3's element
  // sizes, scales 0.12 / 0.125 / 0.13 / 0.14 give 0.128 / 0.183 / 0.122 / 0.192 % on subdivided
  // meshes, 0.178 / 0.079 / 0.123 / 0.162 % on gmsh's own), so the least-squares slope over four
  // levels carries about ±0.3: measured 0.81 (0.79, 0.72, 0.22, 0.18 %) here, 1.17 on gmsh's
  // level-3 mesh. At least 0.7 is convergence; a stalled method gives about 0.
  const fs::path out = fs::temp_directory_path() / "c2d_cli_compare_order";
  fs::remove_all(out);
  std::string output;
  ASSERT_EQ(run("compare " + std::string(C2D_SOURCE_DIR) +
                    "/tests/app/data/hertz_mortar_ladder.toml --levels 4 --methods lagrange "
                    "--jobs 2 --quiet --out " + out.string(),
                &output),
            0)
      << output;
  std::ifstream csv(out / "orders.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header, "method,metric,order,flag");
  std::getline(csv, line);
  const std::string prefix = "lagrange,pressure_profile_l2,";
  ASSERT_EQ(line.rfind(prefix, 0), 0u) << line;
  const double order = std::stod(line.substr(prefix.size()));
  EXPECT_GE(order, 0.7);
  EXPECT_LE(order, 3.0);  // the pressure's square-root edge allows no more than about 1.5
  const std::string text = read_text(out / "compare.md");
  EXPECT_NE(text.find("Observed order of convergence"), std::string::npos);
}

TEST(Cli, CompareRunsEveryMethodOnEveryLevel) {
  // hertz_rigid on two coarse levels (mesh_scale 8 and 4): a row per registered method and
  // level, a verdict computed from the table, three charts; the exact methods agree with
  // lagrange on p_max to 1e-6 on each level, and the profile error falls with refinement.
  const fs::path out = fs::temp_directory_path() / "c2d_cli_compare";
  fs::remove_all(out);
  std::string output;
  ASSERT_EQ(run("compare " + example("hertz_rigid.toml") +
                    " --levels 2 --jobs 2 --set analysis.mesh_scale=8 --quiet --out " + out.string(),
                &output),
            0)
      << output;
  std::ifstream csv(out / "compare.csv");
  std::string line;
  std::getline(csv, line);
  const std::vector<std::string> header = [&] {
    std::vector<std::string> h;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) h.push_back(c);
    return h;
  }();
  auto col = [&](const std::string& name) {
    return static_cast<size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  ASSERT_LT(col("error_profile_l2"), header.size());
  std::map<std::pair<int, std::string>, std::vector<std::string>> rows;
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    if (!line.empty() && line.back() == ',') cells.emplace_back();  // (getline drops it)
    ASSERT_EQ(cells.size(), header.size()) << line;
    rows[{std::stoi(cells[col("level")]), cells[col("method")]}] = cells;
  }
  const auto& methods = c2d::constraints::method_names();
  ASSERT_EQ(rows.size(), 2 * methods.size());
  for (int level : {0, 1}) {
    for (const auto& m : methods)
      EXPECT_EQ((rows[{level, m}][col("status")]), "\"converged\"") << level << " " << m;
    const double ref = std::stod((rows[{level, "lagrange"}][col("p_max")]));
    for (const auto& m : methods) {
      if (!c2d::constraints::is_exact_method(m)) continue;
      EXPECT_NEAR(std::stod((rows[{level, m}][col("p_max")])) / ref, 1.0, 1e-6) << level << " " << m;
    }
  }
  EXPECT_LT(std::stod((rows[{1, "lagrange"}][col("error_profile_l2")])),
            std::stod((rows[{0, "lagrange"}][col("error_profile_l2")])));
  // The Hertz form fitted to the nodal pressures (Ceres) gives the contact half-width within 5 %
  // of 1.6609 mm on both coarse levels (3.4 % at mesh_scale 8, which coarsens the grading slope
  // as well as the sizes; the node-based width is 0.9 % off even on the fine mesh).
  for (int level : {0, 1})
    EXPECT_LT(std::abs(std::stod((rows[{level, "lagrange"}][col("error_fit_b")]))), 0.05) << level;
  const std::string text = read_text(out / "compare.md");
  EXPECT_NE(text.find("Judged by the relative L2 error of the pressure profile (the "
                            "scene's reference, by default). Every method ranked reached"),
            std::string::npos);
  for (const char* stem : {"accuracy_time", "pressure_profiles", "penetration"})
    expect_chart(out, stem);
  // Bad input names the option.
  EXPECT_EQ(run("compare " + example("hertz_rigid.toml") + " --methods lagrange,newton", &output), 2);
  EXPECT_NE(output.find("--methods: expected a comma-separated list of"), std::string::npos) << output;
  EXPECT_EQ(run("compare " + example("cantilever.toml"), &output), 2);
  EXPECT_NE(output.find("compare needs a scene with [[contact]]"), std::string::npos) << output;
}

TEST(Studies, HertzProfileErrorOfTheExactProfileIsZero) {
  // Nodes on the exact profile (fine spacing): only the chord error of linear interpolation
  // remains (< 0.1 %); a profile 10 % too high everywhere inside the zone is 10 % off.
  std::vector<std::pair<double, double>> exact, high;
  for (int i = 0; i <= 2000; ++i) {
    const double x = -3.0 + 3.0 * i / 2000.0;
    const double p = std::abs(x) < 1.0 ? 100.0 * std::sqrt(1.0 - x * x) : 0.0;
    exact.emplace_back(x, p);
    high.emplace_back(x, 1.1 * p);
  }
  EXPECT_LT(c2d::app::hertz_profile_error(exact, 100.0, 1.0), 1e-3);
  EXPECT_NEAR(c2d::app::hertz_profile_error(high, 100.0, 1.0), 0.1, 1e-3);
}

TEST(Studies, HertzInnerProfileErrorSeesOnlyTheInterior) {
  // Hertz's exact pressure at nodes h apart (b = 1 off the node grid): linear interpolation's
  // error over the whole profile is the √(b − |x|) edge's, first order (1.37 % at h = 0.05,
  // 0.66 % at h/2); inside 0.9 b it is the chord's, second order (0.081 %, 0.021 %). A profile
  // 10 % high inside 0.5 b is seen inside: 8.3 %.
  const double b = 1.0, p0 = 100.0;
  const auto nodes = [&](double h, double bump) {
    std::vector<std::pair<double, double>> pts;
    for (int i = -static_cast<int>(3 / h); i <= static_cast<int>(3 / h); ++i) {
      const double x = i * h + 0.001;
      const double p = std::abs(x) < b ? p0 * std::sqrt(1.0 - x * x) : 0.0;
      pts.emplace_back(x, std::abs(x) < 0.5 * b ? bump * p : p);
    }
    return pts;
  };
  using c2d::app::hertz_inner_profile_error;
  using c2d::app::hertz_profile_error;
  const double whole = hertz_profile_error(nodes(0.05, 1.0), p0, b);
  const double whole_half = hertz_profile_error(nodes(0.025, 1.0), p0, b);
  const double inner = hertz_inner_profile_error(nodes(0.05, 1.0), p0, b);
  const double inner_half = hertz_inner_profile_error(nodes(0.025, 1.0), p0, b);
  EXPECT_NEAR(whole / whole_half, 2.0, 0.2);  // h
  EXPECT_GT(inner / inner_half, 3.5);         // h²
  EXPECT_LT(inner, 1e-3);
  EXPECT_NEAR(hertz_inner_profile_error(nodes(0.05, 1.1), p0, b), 0.083, 0.003);
}

TEST(Cli, CompareElasticBlockInnerProfileConvergesFasterThanH) {
  // hertz_block_fast with mortar over compare's three levels (6,164 / 19,290 / 70,112 DOFs):
  // the whole profile's error is ruled by the contact edge (0.54, 0.51, 0.25 %: Hertz's exact
  // pressure sampled at the same nodes scores 0.46, 0.23, 0.12 %), the interior's falls as h²
  // or faster (0.039, 0.011, 0.0019 %: order 2.18 with both exact methods). At least 1.5 is a
  // consistent method; node_to_segment on this non-matching elastic master stalls near 0.1 %.
  const fs::path out = fs::temp_directory_path() / "c2d_cli_compare_inner";
  fs::remove_all(out);
  std::string output;
  ASSERT_EQ(run("compare " + example("hertz_block_fast.toml") +
                    " --levels 3 --methods lagrange,ssn --metric inner --set "
                    "contact.0.detection=mortar --jobs 2 --quiet --out " +
                    out.string(),
                &output),
            0)
      << output;
  std::ifstream csv(out / "orders.csv");
  std::string line;
  std::getline(csv, line);
  for (const std::string method : {"lagrange", "ssn"}) {
    ASSERT_TRUE(std::getline(csv, line));
    const std::string prefix = method + ",pressure_profile_inner_l2,";
    ASSERT_EQ(line.rfind(prefix, 0), 0u) << line;
    EXPECT_GE(std::stod(line.substr(prefix.size())), 1.5) << line;
  }
}

TEST(Cli, PenaltySweepShowsPenetrationFallingUntilIllConditioning) {
  // hertz_rigid (coarse: sizes × 8, grading as shipped) with penalty k = 1e2 ... 1e20: the penetration falls
  // monotonically as long as the runs converge; from some k on the penetration k leaves is
  // below the gaps' round-off (the solve itself, on the condensed surface, keeps its digits:
  // 1e17 still converges here) and every run reports ill_conditioned. Above k = 1e6 (penetration
  // below 1e-4 mm, small against the 0.4 mm contact elements, so the contact zone no longer
  // changes) the penetration is the force over k, 10-fold less per decade (20 % slack), and the
  // p_max error falls with it to the discretisation's own (1e-3 slack for round-off).
  const fs::path out = fs::temp_directory_path() / "c2d_cli_sweep";
  fs::remove_all(out);
  std::string output;
  ASSERT_EQ(run("sweep " + example("hertz_rigid.toml") +
                    " --method penalty --set analysis.mesh_scale=8"
                    // the mesh this test was tuned on: mesh_scale scales the growth slope too
                    " --set body.cylinder.mesh.refine[0].growth=1.03125"
                    " --set contact.penalty.k=1e2:1e20:log:19 --jobs 2 --quiet --out " +
                    out.string(),
                &output),
            0)
      << output;
  // Each case's folder is its run's, with the worker's stdout.log; nothing set aside remains
  // (the run used to leave CASE.part.PID.old holding the log it was writing).
  int cases = 0;
  for (const auto& e : fs::directory_iterator(out)) {
    EXPECT_EQ(e.path().filename().string().find(".part."), std::string::npos) << e.path();
    if (!fs::exists(e.path() / "summary.json")) continue;
    ++cases;
    EXPECT_TRUE(fs::exists(e.path() / "stdout.log")) << e.path();
  }
  EXPECT_EQ(cases, 20);  // 19 values and the baseline (lagrange on the same mesh)
  EXPECT_TRUE(fs::exists(out / "baseline" / "summary.json"));
  std::ifstream csv(out / "sweep.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line.rfind("value,key,status,exit_code,dofs,iterations,time_solve,p_max,error_p_max,"
                       "max_penetration", 0),
            0u);
  std::vector<std::tuple<double, std::string, double, double>> rows;  // k, status, error, pen
  while (std::getline(csv, line)) {
    std::vector<std::string> c;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) c.push_back(x);
    ASSERT_GE(c.size(), 10u) << line;
    const bool ok = c[2] == "\"converged\"";
    rows.emplace_back(std::stod(c[0]), c[2], ok ? std::stod(c[8]) : NAN, ok ? std::stod(c[9]) : NAN);
    // Against lagrange on the same mesh (error_vs_baseline): the penalty's own p_max error,
    // O(1/k), below 1e-4 from k = 1e10 on (the discretisation's 0.1 % taken out).
    if (ok && std::stod(c[0]) >= 1e10) {
      ASSERT_EQ(c.size(), 17u) << line;
      EXPECT_LT(std::abs(std::stod(c[16])), 1e-4) << line;
    }
  }
  ASSERT_EQ(rows.size(), 19u);
  std::sort(rows.begin(), rows.end());
  size_t first_failure = rows.size();
  for (size_t i = 0; i < rows.size(); ++i)
    if (std::get<1>(rows[i]) != "\"converged\"") {
      first_failure = i;
      break;
    }
  ASSERT_LT(first_failure, rows.size()) << "k = 1e20 must be flagged";
  ASSERT_GT(first_failure, 8u) << "k up to 1e10 must converge";
  for (size_t i = first_failure; i < rows.size(); ++i)
    EXPECT_EQ(std::get<1>(rows[i]).rfind("\"failed: ill_conditioned", 0), 0u)
        << std::get<0>(rows[i]) << " " << std::get<1>(rows[i]);
  // Penalty converges to the exactly constrained solution as O(1/k): the p_max error's distance
  // from its limit (the stiffest converged run) shrinks with k once k dominates, until the
  // ill-conditioned solves' round-off (2e-5 of p_max at k ≥ 1e14 here) takes over.
  const double limit = std::get<2>(rows[first_failure - 1]);
  for (size_t i = 1; i < first_failure; ++i) {
    EXPECT_LT(std::get<3>(rows[i]), std::get<3>(rows[i - 1])) << std::get<0>(rows[i]);
    if (std::get<0>(rows[i]) > 1e6) {
      EXPECT_NEAR(std::get<3>(rows[i - 1]) / std::get<3>(rows[i]), 10.0, 2.0) << std::get<0>(rows[i]);
      EXPECT_LE(std::abs(std::get<2>(rows[i]) - limit),
                std::abs(std::get<2>(rows[i - 1]) - limit) * (1 + 1e-3) + 2e-5)
          << std::get<0>(rows[i]);
    }
  }
  const std::string text = read_text(out / "sweep.md");
  EXPECT_NE(text.find("Converged with |p_max error| <= 1 % for contact.penalty.k from"),
            std::string::npos);
  EXPECT_NE(text.find("The seed's rule k = 1e4 x max|K_ij| gives k ="), std::string::npos);
  EXPECT_NE(text.find("Against lagrange on the same mesh"), std::string::npos);
  expect_chart(out, "sweep");
  // A sweep needs exactly one ranged key.
  EXPECT_EQ(run("sweep " + example("hertz_rigid.toml") + " --set contact.penalty.k=1e3", &output), 2);
  EXPECT_NE(output.find("expected one --set key=a:b:log:n"), std::string::npos) << output;
  EXPECT_EQ(run("sweep " + example("hertz_rigid.toml") + " --set contact.penalty.k=1e3:1e5:cubic:3",
                &output),
            2);
  EXPECT_NE(output.find("expected 'log' or 'lin'"), std::string::npos) << output;
}

TEST(Cli, CalibrationRecoversYoungsModulusAndLoadFromNoisySyntheticData) {
  // The cantilever solved with E = 2.6e6 and a 3.9 t tip load gives the "measurements"; they
  // are perturbed by +0.2 % (tip deflection), -0.1 % (support reaction) and +0.15 % (root
  // stress). From E = 2.1e6 and 3 t, the fit must recover E and the load within 1 % (the noise
  // moves E by about the deflection's 0.2 % and the load by the reaction's 0.1 %).
  const fs::path dir = fs::temp_directory_path() / "c2d_cli_calibrate";
  fs::remove_all(dir);
  fs::create_directories(dir);
  ASSERT_EQ(run_args({"run", example("cantilever.toml"), "--set", "material.E=2.6e6", "--set",
                      "load[0].total_force=[0.0, -3.9]", "--quiet", "--out", (dir / "truth").string()}),
            0);
  std::ifstream in(dir / "truth" / "summary.json");
  const nlohmann::json truth = nlohmann::json::parse(in);
  {
    std::ofstream csv(dir / "measured.csv");
    csv << std::setprecision(12) << "probe,value,weight\n"
        << "tip_uy," << truth["probes"]["tip_uy"].get<double>() * 1.002 << ",1\n"
        << "reaction_y," << truth["probes"]["reaction_y"].get<double>() * 0.999 << ",1\n"
        << "sx_max_root," << truth["probes"]["sx_max_root"].get<double>() * 1.0015 << ",1\n";
  }
  std::string output;
  ASSERT_EQ(run("calibrate " + example("cantilever.toml") + " --data " +
                    (dir / "measured.csv").string() +
                    " --fit E,load[0].total_force[1]=-10:-1:lin --quiet --out " + (dir / "fit").string(),
                &output),
            0)
      << output;
  std::ifstream fin(dir / "fit" / "calibrate.json");
  const nlohmann::json fit = nlohmann::json::parse(fin);
  EXPECT_EQ(fit["status"], "converged");
  ASSERT_EQ(fit["parameters"].size(), 2u);
  EXPECT_NEAR(fit["parameters"][0]["fitted"].get<double>() / 2.6e6, 1.0, 0.01);
  EXPECT_NEAR(fit["parameters"][1]["fitted"].get<double>() / -3.9, 1.0, 0.01);
  // Three data for two parameters: standard deviations exist and are of the noise's order.
  for (const auto& p : fit["parameters"]) {
    ASSERT_TRUE(p["sigma"].is_number()) << p;
    EXPECT_LT(p["sigma"].get<double>() / std::abs(p["fitted"].get<double>()), 0.01) << p;
  }
  // Bad input: an unknown probe names the file and line.
  {
    std::ofstream csv(dir / "bad.csv");
    csv << "probe,value\ntip_ux,1.0\n";
  }
  EXPECT_EQ(run("calibrate " + example("cantilever.toml") + " --data " + (dir / "bad.csv").string() +
                    " --fit E",
                &output),
            2);
  EXPECT_NE(output.find("bad.csv:2: expected the name of a [[probe]]"), std::string::npos) << output;
}

TEST(Cli, CompareOnAFrictionalHertzCase) {
  // examples/cattaneo_mindlin.toml on a coarse level (mesh_scale 4, 1,144 DOFs): a row per
  // registered method, each converged or failed with a named status (lagrange, ssn, ipopt and
  // auglag converged), no NaN; the exact methods
  // agree on the stick zone's length (1e-9) and the tangential force (1e-6 of Q = 150), the
  // regularised ones within 2 % of the stick length, every converged run carries Q to 1e-3;
  // the verdict is taken on the shear profile.
  const fs::path out = fs::temp_directory_path() / "c2d_cli_compare_friction";
  fs::remove_all(out);
  std::string output;
  ASSERT_EQ(run("compare " + example("cattaneo_mindlin.toml") +
                    " --levels 1 --jobs 2 --set analysis.mesh_scale=4 --quiet --out " + out.string(),
                &output),
            0)
      << output;
  const c2d::app::CsvTable t = c2d::app::read_csv((out / "compare.csv").string());
  std::map<std::string, size_t> row;
  for (size_t i = 0; i < t.rows.size(); ++i) row[t.rows[i][t.column("method")]] = i;
  ASSERT_EQ(row.size(), c2d::constraints::method_names().size());
  const int status = t.column("status"), stick = t.column("stick_length"),
            q = t.column("tangential_force"), shear = t.column("error_shear_profile_l2");
  auto status_of = [&](size_t i) {  // the status cell without its quotes
    std::string st = t.rows[i][status];
    st.erase(std::remove(st.begin(), st.end(), '"'), st.end());
    return st;
  };
  for (const auto& m : {"lagrange", "ssn", "ipopt", "auglag"})
    ASSERT_EQ(status_of(row.at(m)), "converged") << m;
  const double stick_ref = t.number(row.at("lagrange"), stick);
  for (const auto& [m, i] : row) {
    const std::string st = status_of(i);
    ASSERT_TRUE(st == "converged" || st.rfind("failed: ", 0) == 0) << m << ": " << st;
    for (const std::string& cell : t.rows[i]) {
      EXPECT_EQ(cell.find("nan"), std::string::npos) << m;
      EXPECT_EQ(cell.find("inf"), std::string::npos) << m;
    }
    if (st != "converged") continue;
    const double tol = c2d::constraints::is_exact_method(m) ? 1e-9 : 2e-2;
    EXPECT_NEAR(t.number(i, stick) / stick_ref, 1.0, tol) << m;
    EXPECT_NEAR(std::abs(t.number(i, q)), 150.0, 0.15) << m;
    EXPECT_TRUE(std::isfinite(t.number(i, shear))) << m;
  }
  EXPECT_NEAR(std::abs(t.number(row.at("ssn"), q)), std::abs(t.number(row.at("lagrange"), q)),
              1.5e-4);
  const std::string text = read_text(out / "compare.md");
  EXPECT_NE(text.find("relative L2 error of the shear profile (Cattaneo–Mindlin)"),
            std::string::npos)
      << text;
}

TEST(Cli, StressSuiteEndsEveryMethodWithANamedStatus) {
  // examples/stress/: every method through `compare`; the statuses each scene's comment
  // predicts, exit codes 0 or 1 (never a crash), no NaN or inf anywhere in the table, and the
  // load carried where a method converges (1e-6 relative: equilibrium of the contact forces).
  struct Expect {
    const char* scene;
    std::map<std::string, std::string> status;  // method -> status prefix
    double load;                                // total force where converged (0: not checked)
  };
  const std::string ok = "\"converged", singular = "\"failed: singular";
  const std::vector<Expect> cases = {
      {"penalty_ill_conditioned",  // k = 1e20, resolved on the condensed surface
       {{"penalty", ok}, {"adaptive_penalty", ok}, {"lagrange", ok}, {"auglag", ok}, {"ipopt", ok}, {"ssn", ok}},
       1000.0},
      {"redundant_rows",
       {{"penalty", ok}, {"adaptive_penalty", ok}, {"lagrange", singular}, {"auglag", ok}, {"ipopt", ok}, {"ssn", singular}},
       0.0},
      {"unsupported_body",
       {{"penalty", singular}, {"adaptive_penalty", singular}, {"lagrange", singular}, {"auglag", singular},
        {"ipopt", singular}, {"ssn", singular}},
       0.0},
      {"big_step",
       {{"penalty", ok}, {"adaptive_penalty", ok}, {"lagrange", ok}, {"auglag", ok}, {"ipopt", ok}, {"ssn", ok}},
       0.0},
      {"punch_edge",
       {{"penalty", ok}, {"adaptive_penalty", ok}, {"lagrange", ok}, {"auglag", ok}, {"ipopt", ok}, {"ssn", ok}},
       2000.0},
  };
  for (const auto& c : cases) {
    const fs::path out = fs::temp_directory_path() / (std::string("c2d_stress_") + c.scene);
    fs::remove_all(out);
    std::string output;
    ASSERT_EQ(run("compare " + std::string(C2D_SOURCE_DIR) + "/examples/stress/" + c.scene +
                      ".toml --jobs 2 --quiet --out " + out.string(),
                  &output),
              0)
        << c.scene << ": " << output;
    const std::string all = read_text(out / "compare.csv");
    std::string lower = all;
    std::transform(lower.begin(), lower.end(), lower.begin(), ::tolower);
    EXPECT_EQ(lower.find("nan"), std::string::npos) << c.scene;
    EXPECT_EQ(lower.find("inf"), std::string::npos) << c.scene;
    std::stringstream lines(all);
    std::string line;
    std::getline(lines, line);
    int rows = 0;
    while (std::getline(lines, line)) {
      // level,method,mesh_scale,dofs,"status",exit_code,iterations,newton,4 times,wall,p_max,
      // contact_length,total_force,...
      const auto q1 = line.find('"'), q2 = line.find('"', q1 + 1);
      const std::string status = line.substr(q1, q2 - q1 + 1);
      std::vector<std::string> cells;
      std::stringstream head(line.substr(0, q1)), tail(line.substr(q2 + 2));
      for (std::string x; std::getline(head, x, ',');) cells.push_back(x);
      const std::string method = cells[1];
      std::vector<std::string> rest;
      for (std::string x; std::getline(tail, x, ',');) rest.push_back(x);
      const int exit_code = std::stoi(rest[0]);
      // A method without a stated prediction must still end with a named status.
      const auto predicted = c.status.find(method);
      if (predicted != c.status.end())
        EXPECT_EQ(status.rfind(predicted->second, 0), 0u) << c.scene << " " << method << ": " << status;
      else
        EXPECT_TRUE(status == "\"converged\"" || status.rfind("\"failed: ", 0) == 0)
            << c.scene << " " << method << ": " << status;
      EXPECT_TRUE(exit_code == 0 || exit_code == 1) << c.scene << " " << method;
      if (c.load > 0 && status == "\"converged\"") {
        EXPECT_NEAR(std::stod(rest[10]), c.load, 1e-6 * c.load) << c.scene << " " << method;
      }
      ++rows;
    }
    EXPECT_EQ(rows, static_cast<int>(c2d::constraints::method_names().size())) << c.scene;
  }
}

TEST(Cli, CompareGivesTheSameNumbersWhateverTheJobs) {
  // punch_edge, all six methods, with 1 and with 2 concurrent runs: every column but the times
  // is identical (each run is its own deterministic process; rows are kept in case order).
  std::map<int, std::vector<std::string>> tables;
  for (int jobs : {1, 2}) {
    const fs::path out = fs::temp_directory_path() / ("c2d_jobs_" + std::to_string(jobs));
    fs::remove_all(out);
    ASSERT_EQ(run("compare " + std::string(C2D_SOURCE_DIR) +
                  "/examples/stress/punch_edge.toml --quiet --jobs " + std::to_string(jobs) +
                  " --out " + out.string()),
              0);
    std::ifstream csv(out / "compare.csv");
    std::string header, line;
    std::getline(csv, header);
    std::vector<std::string> columns;
    std::stringstream hs(header);
    for (std::string c; std::getline(hs, c, ',');) columns.push_back(c);
    while (std::getline(csv, line)) {
      std::vector<std::string> cells;
      std::stringstream ls(line);
      for (std::string c; std::getline(ls, c, ',');) cells.push_back(c);
      std::string kept;
      for (size_t i = 0; i < cells.size() && i < columns.size(); ++i)
        if (columns[i].rfind("time_", 0) != 0 && columns[i] != "wall") kept += cells[i] + ",";
      tables[jobs].push_back(kept);
    }
  }
  ASSERT_EQ(tables[1].size(), 6u);
  EXPECT_EQ(tables[1], tables[2]);
}

TEST(Cli, AdaptiveRunWritesItsCyclesAndPlotDrawsEveryField) {
  // hertz_rigid_coarse.toml with --adapt: the cycles in adapt.csv (ξ_g falling to <= 1), one
  // VTU per cycle, the summary's adapt block; then every plot field, the mesh comparison and
  // the errors plot reports.
  const fs::path out = fs::temp_directory_path() / "c2d_cli_adapt";
  fs::remove_all(out);
  std::string output;
  ASSERT_EQ(run("run " + example("hertz_rigid_coarse.toml") + " --adapt max_cycles=8 --out " +
                    out.string(), &output), 0) << output;
  EXPECT_NE(output.find("adapt      xi_g = "), std::string::npos) << output;
  const c2d::app::CsvTable table = c2d::app::read_csv((out / "adapt.csv").string());
  ASSERT_GE(table.rows.size(), 3u);
  const int xi = table.column("xi_g"), p = table.column("p_max");
  EXPECT_LE(table.number(table.rows.size() - 1, xi), 1.0);
  EXPECT_GT(table.number(0, xi), 1.0);
  EXPECT_NEAR(table.number(table.rows.size() - 1, p) / 383.29, 1.0, 0.01);
  for (size_t c = 0; c < table.rows.size(); ++c) {
    char name[32];
    std::snprintf(name, sizeof name, "cycle_%02zu.vtu", c);
    EXPECT_TRUE(fs::exists(out / name)) << name;
  }
  std::ifstream in(out / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_TRUE(s["adapt"]["reached"].get<bool>());
  EXPECT_EQ(s["adapt"]["cycles"].size(), table.rows.size());
  EXPECT_EQ(s["mesh"]["dofs"], s["adapt"]["cycles"].back()["dofs"]);

  ASSERT_EQ(run("plot " + out.string() + " --field all --zoom -4,0,4,3 --edges", &output), 0)
      << output;
  for (const auto& f : c2d::app::plot_fields()) expect_chart(out, "plot_" + f);
  expect_chart(out, "adapt_meshes");
  EXPECT_NE(output.find("elements with xi_e > 1"), std::string::npos) << output;
  ASSERT_EQ(run("plot " + out.string() + " --cycle 0 --field error", &output), 0) << output;
  expect_chart(out, "plot_error_cycle00");

  EXPECT_EQ(run("plot " + out.string() + " --field bogus", &output), 2);
  EXPECT_NE(output.find("--field: expected sx|sy|sxy|vm|p1|p2|ux|uy|error or all, found 'bogus'"),
            std::string::npos) << output;
  EXPECT_EQ(run("plot " + out.string() + " --zoom 1,2,3", &output), 2);
  EXPECT_NE(output.find("--zoom: expected x0,y0,x1,y1"), std::string::npos) << output;
  EXPECT_EQ(run("plot " + out.string() + " --cycle 40", &output), 2);
  EXPECT_NE(output.find("--cycle 40: "), std::string::npos) << output;
  EXPECT_EQ(run("plot /nonexistent/c2d_plot", &output), 2);
  EXPECT_NE(output.find("/nonexistent/c2d_plot: not a folder"), std::string::npos) << output;
  EXPECT_EQ(run("run " + example("legacy/two_blocks_gap.dat") + " --adapt --out " + out.string(), &output), 2);
  EXPECT_NE(output.find("adaptivity needs bodies meshed from shapes"), std::string::npos) << output;
}

TEST(Cli, InputFaultsAreNamedAsSuchWithExitTwo) {
  // Issue 16, finding 8: an unknown --method, a scene path that is a folder, and --out naming a
  // file or a folder that cannot be created are input errors (exit 2) that name the input.
  std::string output;
  const fs::path dir = fs::temp_directory_path() / ("c2d_cli_faults_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "a_file") << "x";
  EXPECT_EQ(run_args({"run", example("hertz_rigid_fast.toml"), "--method", "newton"}, &output), 2);
  EXPECT_NE(output.find("--method: expected penalty | adaptive_penalty"), std::string::npos) << output;
  EXPECT_NE(output.find("found 'newton'"), std::string::npos) << output;
  EXPECT_EQ(run_args({"run", dir.string()}, &output), 2);
  EXPECT_NE(output.find("expected a scene file (.toml or .dat), found a folder"), std::string::npos) << output;
  EXPECT_EQ(run_args({"run", example("hertz_rigid_fast.toml"), "--out", (dir / "a_file").string()}, &output), 2);
  EXPECT_NE(output.find("a_file: expected an output folder, found a file"), std::string::npos) << output;
  EXPECT_EQ(run_args({"run", example("hertz_rigid_fast.toml"), "--out", (dir / "a_file" / "sub").string()}, &output), 2);
  EXPECT_NE(output.find("a_file: expected an output folder"), std::string::npos) << output;
  fs::remove_all(dir);
}

TEST(Cli, AnOutputFolderNeverMixesTwoRuns) {
  // Issue 16, finding 7: a run writes into a work folder beside the target and swaps it in
  // whole at the end. A failed run replaces an earlier converged one (its summary says failed,
  // no step file of the earlier run stays); a refused input leaves no folder; two runs into one
  // folder at once leave one of them whole; no work folder remains.
  const fs::path dir = fs::temp_directory_path() / ("c2d_cli_folders_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string out = (dir / "out").string();
  std::string output;
  ASSERT_EQ(run_args({"run", example("two_cantilevers.toml"), "--out", out}, &output), 0) << output;
  ASSERT_TRUE(fs::exists(dir / "out" / "step_0002.vtu"));
  // The terminal names the folder and the files the run wrote (found in the work folder then).
  EXPECT_NE(output.find(out + "/ (summary.json, results.pvd, nodes.csv, contact.csv"), std::string::npos)
      << output;
  EXPECT_EQ(run_args({"run", example("cantilever.toml"), "--set", "support[0].on.edge=bottom", "--set",
                      "support[0].fix=[\"uy\"]", "--out", out, "--quiet"}, &output), 1);
  std::ifstream in(dir / "out" / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(s["status"].get<std::string>().rfind("failed: singular", 0), 0u) << s["status"];
  EXPECT_FALSE(fs::exists(dir / "out" / "step_0002.vtu"));
  EXPECT_FALSE(fs::exists(dir / "out" / "contact.csv"));
  EXPECT_EQ(run_args({"run", example("cantilever.toml"), "--set", "support[0].on.edge=nowhere", "--out",
                      (dir / "refused").string(), "--quiet"}, &output), 2);
  EXPECT_FALSE(fs::exists(dir / "refused"));
  // Two runs at once into one folder, with different methods: the folder is one of them.
  const std::string both = (dir / "both").string();
  std::thread other([&] {
    std::string o;
    c2d::app::run_process(C2D_BINARY, {"run", example("hertz_rigid_fast.toml"), "--method", "penalty", "--out", both, "--quiet"},
                          (dir / "other.log").string());
  });
  EXPECT_EQ(run_args({"run", example("hertz_rigid_fast.toml"), "--method", "ssn", "--out", both, "--quiet"}, &output), 0);
  other.join();
  std::ifstream sj(dir / "both" / "summary.json");
  const std::string method = nlohmann::json::parse(sj)["solver"]["backend"];
  const std::string text = read_text(dir / "both" / "run.log");
  EXPECT_NE(text.find("with " + method + " contact"), std::string::npos) << method;
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".part."), std::string::npos) << e.path();
  fs::remove_all(dir);
}

TEST(Cli, SigintEndsARunAsInterruptedWithExit130) {
  // Issue 16, finding 7: SIGINT during the solve (a 110k-DOF contact run that takes seconds)
  // ends with exit 130 and an output folder whose summary.json says "interrupted".
  const fs::path dir = fs::temp_directory_path() / ("c2d_cli_sigint_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string out = (dir / "out").string(), binary = C2D_BINARY,
                    scene = example("two_cantilevers.toml");
  std::vector<std::string> words{binary, "run", scene, "--set", "analysis.mesh_scale=0.3", "--out", out, "--quiet"};
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, binary.c_str(), nullptr, nullptr, argv.data(), environ), 0);
  // Signal once the solve has begun (its run.log, written as the run goes, says so).
  const fs::path log = dir / ("out.part." + std::to_string(pid)) / "run.log";
  for (int i = 0; i < 600; ++i) {
    const std::string t = read_text(log);
    if (t.find("solving") != std::string::npos) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  ::kill(pid, SIGINT);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  std::ifstream in(dir / "out" / "summary.json");
  ASSERT_TRUE(in.good());
  EXPECT_EQ(nlohmann::json::parse(in)["status"], "interrupted");
  EXPECT_TRUE(fs::exists(dir / "out" / "run.log"));
  fs::remove_all(dir);
}

TEST(Cli, TiedBlocksReportTheirConstraints) {
  // examples/tied_blocks.toml: a mortar tie across non-matching meshes and an `equal` top under
  // a corner force carry the exact uniaxial stress σ_y = −F/w = −5, the top moving by
  // −F (H1 + H2) / (E w) = −7.5e-3; summary.json and constraints.csv list the rows.
  const fs::path out = fs::temp_directory_path() / "c2d_cli_tied_blocks";
  fs::remove_all(out);
  ASSERT_EQ(run("run " + example("tied_blocks.toml") + " --out " + out.string() + " --quiet"), 0);
  std::ifstream in(out / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(s["status"], "converged");
  EXPECT_NEAR(s["probes"]["top_uy"].get<double>(), -7.5e-3, 1e-12);
  EXPECT_NEAR(s["probes"]["sy_center"].get<double>(), -5.0, 1e-9);
  ASSERT_EQ(s["constraints"].size(), 2u);
  int rows = 0;
  for (const auto& c : s["constraints"]) {
    EXPECT_LT(c["max_residual"].get<double>(), 1e-12) << c["name"];
    rows += c["rows"].get<int>();
  }
  EXPECT_EQ(s["constraints"][0]["name"], "glue");
  EXPECT_EQ(s["constraints"][1]["type"], "equal");
  std::ifstream csv(out / "constraints.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "row,constraint,type,multiplier,residual");
  int lines = 0;
  while (std::getline(csv, line)) ++lines;
  EXPECT_EQ(lines, rows);
}

// Issue 20, item 4: the terminal summary rounds (times to 3 significant figures, pressures and
// forces to 5) and names the scene's units; summary.json keeps full precision.
TEST(Cli, TerminalSummaryRoundsAndNamesUnits) {
  const nlohmann::json s = {
      {"status", "converged"},
      {"units", "N, mm, MPa"},
      {"method", "lagrange"},
      {"time_s", {{"mesh", 0.0123456}, {"assemble", 1.23456e-3}, {"solve", 0.5312}, {"total", 1.17049}}},
      {"contact",
       {{"status", "converged"}, {"iterations", 10}, {"active_nodes", 68}, {"slave_nodes", 148},
        {"p_max", 383.3211234}, {"length", 1.675473}, {"total_force", 500.0000001},
        {"max_penetration", 2.61e-18}, {"measured_penetration", 2.61e-18}}},
      {"probes", {{"half_width", 1.675473211}}}};
  const std::string text = c2d::app::terminal_summary(s, "/tmp/x", "/nonexistent");
  EXPECT_NE(text.find("total 1.17 s"), std::string::npos) << text;
  EXPECT_NE(text.find("assemble 0.00123 s"), std::string::npos) << text;
  EXPECT_NE(text.find("p_max 383.32 MPa"), std::string::npos) << text;
  EXPECT_NE(text.find("length 1.6755 mm"), std::string::npos) << text;
  EXPECT_NE(text.find("total force 500 N"), std::string::npos) << text;
  EXPECT_NE(text.find("half_width = 1.67547\n"), std::string::npos) << text;
}

// Issue 20, item 3 (in part): the run charts label their axes with the scene's units.
TEST(Cli, RunChartsLabelAxesWithTheSceneUnits) {
  const c2d::app::Units u = c2d::app::parse_units("N, mm, MPa");
  EXPECT_EQ(u.force, "N");
  EXPECT_EQ(u.length, "mm");
  EXPECT_EQ(u.stress, "MPa");
  EXPECT_EQ(c2d::app::parse_units("t, m, t/m2").stress, "t/m2");
  EXPECT_EQ(c2d::app::axis_label("x", ""), "x");
  const fs::path out = fs::temp_directory_path() / "c2d_cli_units";
  fs::remove_all(out);
  ASSERT_EQ(run("run " + example("hertz_rigid_fast.toml") + " --out " + out.string() + " --quiet"),
            0);
  auto text = [&](const char* file) { return read_text(out / file); };
  const std::string pressure = text("pressure.svg"), deformed = text("deformed.svg");
  EXPECT_NE(pressure.find("pressure [MPa]"), std::string::npos);
  EXPECT_NE(pressure.find("x [mm]"), std::string::npos);
  EXPECT_NE(deformed.find("y [mm]"), std::string::npos);
  EXPECT_NE(deformed.find("von Mises [MPa]"), std::string::npos);
  // Issue 35, item 5: a small-strain run's magnification is a round number, said as drawn
  // (8 % of the model over a largest displacement of 0.0221 mm is 2560: drawn at 2000).
  EXPECT_NE(deformed.find("Deformed mesh (displacements ×2000), coloured by von Mises"),
            std::string::npos);
}

// Issue 35, item 5: a finite-strain run (elastica: a tip deflection half the beam's length) is
// drawn at true scale; before, its deformed.png shrank the displacements (x 0.162).
TEST(Cli, FiniteStrainRunIsDrawnAtTrueScale) {
  const fs::path out = fs::temp_directory_path() / "c2d_cli_true_scale";
  fs::remove_all(out);
  ASSERT_EQ(run("run " + example("elastica.toml") + " --out " + out.string() + " --quiet"), 0);
  const std::string svg = read_text(out / "deformed.svg");
  EXPECT_NE(svg.find(">Deformed mesh (true scale, finite strain), coloured by von Mises "
                           "(smoothed)</tspan>"),
            std::string::npos);
  EXPECT_EQ(svg.find("displacements x"), std::string::npos);
  fs::remove_all(out);
}

// A slender model (slender_floor: 12 wide, 1.3 tall) keeps a window a third as tall as it is
// wide, centred on it, so the colour bar beside the equal-scale plot has room for its ticks; a
// compact one keeps gnuplot's own ranges.
TEST(Charts, SlenderModelsGetAWindowTallEnoughForTheColourBar) {
  const Eigen::AlignedBox2d slender(c2d::Vec2(0.0, -1.0), c2d::Vec2(12.0, 0.3));
  const std::string w = c2d::app::slender_window(slender);
  double x0, x1, y0, y1;
  ASSERT_EQ(std::sscanf(w.c_str(), "set xrange [%lf:%lf]\nset yrange [%lf:%lf]", &x0, &x1, &y0, &y1),
            4)
      << w;
  EXPECT_NEAR(x0, -0.24, 1e-12);  // 2 % of the width either side
  EXPECT_NEAR(x1, 12.24, 1e-12);
  EXPECT_NEAR((y1 - y0) / (x1 - x0), 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(0.5 * (y0 + y1), -0.35, 1e-12);
  EXPECT_EQ(c2d::app::slender_window(Eigen::AlignedBox2d(c2d::Vec2(0, 0), c2d::Vec2(2, 1))), "");
  EXPECT_EQ(c2d::app::slender_window(Eigen::AlignedBox2d()), "");
}

// Issue 35, item 4: the sweep chart's x range holds every value swept (the failed ones drawn
// as red lines) and the seed rule's k, so that none of their markers falls beside the axes.
TEST(Studies, SweepChartRangeHoldsEveryMarker) {
  // The values of a sweep whose ends failed, the seed's k between: whole decades beyond them.
  const std::vector<double> values = {1e-6, 10.0, 1e5, 1e9, 1e13, 1e30};
  const auto [lo, hi] = c2d::app::sweep_x_range(values, 1.6073992e10, true);
  EXPECT_DOUBLE_EQ(lo, 1e-7);
  EXPECT_DOUBLE_EQ(hi, 1e31);
  // A seed rule outside the values swept widens the range to it.
  const auto [lo2, hi2] = c2d::app::sweep_x_range({1e3, 1e5}, 3e8, true);
  EXPECT_DOUBLE_EQ(lo2, 100.0);
  EXPECT_DOUBLE_EQ(hi2, 1e9);
  EXPECT_LT(3e8, hi2);
  // Linear: 5 % of the span either side.
  const auto [lo3, hi3] = c2d::app::sweep_x_range({1.0, 2.0, 3.0}, std::nan(""), false);
  EXPECT_DOUBLE_EQ(lo3, 0.9);
  EXPECT_DOUBLE_EQ(hi3, 3.1);
}

// A study's cases get cores / jobs threads for BLAS and OpenMP through their environment (issue
// 19, item 4): two factorisations' OpenBLAS threads on the same cores had slowed one 20x and
// flipped compare's ranking with --jobs 2. The child sees the value given, replacing the
// parent's, and the rest of the parent's environment.
TEST(Cli, StudyCasesGetTheirThreadCountsThroughTheEnvironment) {
  const auto dir = std::filesystem::temp_directory_path() / "c2d_env_test";
  std::filesystem::create_directories(dir);
  const std::string log = (dir / "env.log").string();
  ::setenv("C2D_ENV_TEST_KEEP", "kept", 1);
  ::setenv("OMP_NUM_THREADS", "7", 1);
  const c2d::app::ProcessOutcome p =
      c2d::app::run_process("/usr/bin/env", {}, log, {"OMP_NUM_THREADS=1"});
  ::unsetenv("OMP_NUM_THREADS");
  ASSERT_TRUE(p.started) << p.error;
  std::ifstream in(log);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("OMP_NUM_THREADS=1\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("OMP_NUM_THREADS=7"), std::string::npos) << text;
  EXPECT_NE(text.find("C2D_ENV_TEST_KEEP=kept"), std::string::npos);
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  EXPECT_EQ(c2d::app::threads_per_case(1), cores);
  EXPECT_EQ(c2d::app::threads_per_case(2), std::max(1, cores / 2));
  EXPECT_EQ(c2d::app::threads_per_case(1000), 1);
  EXPECT_NE(c2d::app::timing_note(2).find("thread(s) for BLAS and OpenMP"), std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST(Cli, ContactRunDrawsTheContactZone) {
  // hertz_rigid_fast: the contact-zone chart is written (PNG and SVG, units on the axes), and
  // the field it draws has Hertz's subsurface maximum of von Mises on the axis: 0.557 p0 at
  // z = 0.70 b for plane strain, ν = 0.3 (Johnson §4.2; p0 = 383.51 MPa, b = 1.6609 mm), the
  // depth within 5 % (the nodes' spacing there) and the value within 2 %.
  const fs::path out = fs::temp_directory_path() / "c2d_cli_contact_zone";
  fs::remove_all(out);
  std::string output;
  ASSERT_EQ(run("run " + example("hertz_rigid_fast.toml") + " --quiet --out " + out.string(),
                &output),
            0)
      << output;
  expect_chart(out, "contact_zone");
  const std::string text = read_text(out / "contact_zone.svg");
  EXPECT_NE(text.find("x [mm]"), std::string::npos);
  EXPECT_NE(text.find("vm [MPa]"), std::string::npos);
  const c2d::app::CsvTable t = c2d::app::read_csv((out / "nodes.csv").string());
  const int x = t.column("x"), y = t.column("y"), vm = t.column("vm");
  size_t best = 0;
  for (size_t i = 0; i < t.rows.size(); ++i)
    if (std::abs(t.number(i, x)) < 1e-9 && t.number(i, vm) > t.number(best, vm)) best = i;
  EXPECT_NEAR(t.number(best, y) / (0.70 * 1.6609), 1.0, 0.05) << t.number(best, y);
  EXPECT_NEAR(t.number(best, vm) / (0.557 * 383.51), 1.0, 0.02) << t.number(best, vm);
}
