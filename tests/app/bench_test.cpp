// `contact2d bench --quick`: the structure of bench.csv and bench.md (no timing thresholds:
// benchmarks report figures), and the ladder's accuracy trend against its references.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "app/studies/bench.hpp"
#include "app/process.hpp"

namespace fs = std::filesystem;

namespace {

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream ss(line);
  for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

}  // namespace

TEST(Bench, LogLogSlopeRecoversAPowerLaw) {
  // y = 3 x^1.5 exactly: slope 1.5 to round-off (1e-12); fewer than two points: NaN.
  std::vector<double> x{1e4, 1e5, 1e6}, y;
  for (double v : x) y.push_back(3.0 * std::pow(v, 1.5));
  EXPECT_NEAR(c2d::app::loglog_slope(x, y), 1.5, 1e-12);
  EXPECT_TRUE(std::isnan(c2d::app::loglog_slope({1e4}, {2.0})));
}

TEST(Bench, QuickLadderWritesAValidTableWhoseAccuracyImprovesWithDofs) {
  const fs::path out = fs::temp_directory_path() / ("c2d_bench_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const auto p = c2d::app::run_process(C2D_BINARY, {"bench", "--quick", "--quiet", "--out", out.string()},
                                       out.string() + ".log");
  ASSERT_EQ(p.exit_code, 0) << "see " << out.string() << ".log";

  std::ifstream csv(out / "bench.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line + "\n", c2d::app::kBenchCsvHeader);
  const std::vector<std::string> header = split_csv(line);
  auto col = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return static_cast<size_t>(it - header.begin());
  };
  std::vector<std::vector<std::string>> rows;
  while (std::getline(csv, line)) {
    rows.push_back(split_csv(line));
    ASSERT_EQ(rows.back().size(), header.size()) << line;
  }
  ASSERT_EQ(rows.size(), c2d::app::bench_ladder(true).size());
  // Every run converged, with DOFs, positive phase times and a peak memory.
  std::map<std::string, std::vector<std::pair<double, double>>> trend;  // family element -> (dofs, accuracy)
  for (const auto& r : rows) {
    EXPECT_EQ(r[col("status")], "\"converged\"") << r[col("family")] << " " << r[col("method")];
    const double dofs = std::stod(r[col("dofs")]);
    EXPECT_GT(dofs, 1000);
    for (const char* t : {"time_mesh", "time_solve", "time_total", "wall", "peak_rss_mb"})
      EXPECT_GT(std::stod(r[col(t)]), 0.0) << t;
    if (r[col("family")] != "two_cantilevers") {  // load-stepped: assembly is inside each Newton step
      EXPECT_GT(std::stod(r[col("time_assemble")]), 0.0);
    }
    EXPECT_LE(std::stod(r[col("time_total")]), std::stod(r[col("wall")]));
    if (r[col("family")] == "elasticity" || r[col("family")] == "hertz_rigid")
      trend[r[col("family")] + " " + r[col("element")]].emplace_back(dofs, std::stod(r[col("accuracy")]));
    if (r[col("family")] == "methods") {
      // Every method reaches the Hertz profile within 2 % on the time-to-accuracy meshes
      // (references: Johnson §4.2, b and p0 of the scene), and has a contact overhead.
      EXPECT_EQ(r[col("accuracy_measure")], "pressure_profile_l2");
      EXPECT_LT(std::stod(r[col("accuracy")]), 0.02) << r[col("method")];
      EXPECT_GT(std::stod(r[col("contact_overhead")]), 0.0) << r[col("method")];
    }
  }
  // Accuracy improves with DOFs at every rung: the cantilever's tip against Timoshenko beam
  // theory (it converges from above to the 0.13 % the 2D model differs by), Hertz's pressure
  // profile against Johnson's.
  ASSERT_EQ(trend.size(), 2u);
  for (auto& [family, pts] : trend) {
    std::sort(pts.begin(), pts.end());
    ASSERT_GE(pts.size(), 2u) << family;
    for (size_t i = 1; i < pts.size(); ++i)
      EXPECT_LT(pts[i].second, pts[i - 1].second) << family << " at " << pts[i].first << " DOFs";
  }
  // bench.md names every target with a measured figure or "not run", and the charts exist.
  std::ifstream md_in(out / "bench.md");
  std::stringstream md;
  md << md_in.rdbuf();
  for (const char* target : {"refill assembly, T3", "refill assembly, T6", "1M-DOF linear elastic solve",
                             "peak memory", "contact overhead", "Hertz rigid flat, time to accuracy",
                             "Hertz elastic block, time to accuracy", "contact detection at 1M DOFs",
                             "load-stepped contact, lagrange and ssn", "Cattaneo–Mindlin example",
                             "slender beam on a floor"})
    EXPECT_NE(md.str().find(target), std::string::npos) << target;
  // --quick steps the drag with lagrange alone: the rows that speak for more methods than ran
  // say so instead of a verdict.
  for (const char* row : {"| load-stepped contact, every method", "| load-stepped contact, lagrange and ssn"}) {
    const size_t at = md.str().find(row);
    ASSERT_NE(at, std::string::npos) << row;
    const std::string line = md.str().substr(at, md.str().find('\n', at) - at);
    EXPECT_NE(line.find("not run with"), std::string::npos) << line;
    EXPECT_NE(line.find("| not run |"), std::string::npos) << line;
  }
  for (const char* chart : {"time_vs_dofs.png", "time_vs_dofs.svg", "accuracy_vs_time.png", "accuracy_vs_time.svg"})
    EXPECT_TRUE(fs::exists(out / chart)) << chart;
  // bench.html: a table row per CSV row, both charts inline, the targets as its verdict.
  std::ifstream html_in(out / "bench.html");
  const std::string html((std::istreambuf_iterator<char>(html_in)),
                         std::istreambuf_iterator<char>());
  const size_t body = html.find("<tbody>"), body_end = html.find("</tbody>");
  ASSERT_NE(body, std::string::npos);
  size_t table_rows = 0, svgs = 0;
  for (size_t at = html.find("<tr>", body); at < body_end; at = html.find("<tr>", at + 1))
    ++table_rows;
  for (size_t at = html.find("<svg class=\"chart\""); at != std::string::npos;
       at = html.find("<svg class=\"chart\"", at + 1))
    ++svgs;
  EXPECT_EQ(table_rows, rows.size());
  EXPECT_EQ(svgs, 2u);
  EXPECT_NE(html.find("<section id=\"verdict\">\n<h2>Verdict</h2>\n<div class=\"scroll\"><table>"),
            std::string::npos);
  fs::remove_all(out);
  fs::remove(out.string() + ".log");
}
