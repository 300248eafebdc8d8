// The post-processor's geometry: isoband clipping and reading back the VTU that run writes.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "app/report/field_plot.hpp"
#include "app/report/gnuplot.hpp"
#include "core/errors.hpp"
#include "core/model.hpp"
#include "core/probes.hpp"
#include "core/scene.hpp"
#include "core/writers.hpp"
#include "nonlinear/load_stepper.hpp"

using namespace c2d;

namespace {

double polygon_area(const std::vector<Vec2>& p) {
  double a = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    const Vec2& u = p[i];
    const Vec2& v = p[(i + 1) % p.size()];
    a += u.x() * v.y() - v.x() * u.y();
  }
  return 0.5 * a;
}

}  // namespace

TEST(ClipBand, BandsOfALinearFieldHaveTheirExactAreas) {
  // v = x on the unit right triangle: the band a <= x <= b has area ∫_a^b (1 - x) dx.
  const std::array<Vec2, 3> x = {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1)};
  const std::array<double, 3> v = {0.0, 1.0, 0.0};
  double total = 0.0;
  for (int k = 0; k < 8; ++k) {
    const double a = k / 8.0, b = (k + 1) / 8.0;
    const auto poly = app::clip_band(x, v, a, b);
    ASSERT_GE(poly.size(), 3u) << "band " << k;
    const double exact = (b - b * b / 2) - (a - a * a / 2);
    EXPECT_NEAR(polygon_area(poly), exact, 1e-15) << "band " << k;
    total += polygon_area(poly);
  }
  EXPECT_NEAR(total, 0.5, 1e-15);
  EXPECT_TRUE(app::clip_band(x, v, 1.5, 2.0).empty());
  EXPECT_NEAR(polygon_area(app::clip_band(x, v, -1.0, 2.0)), 0.5, 1e-15);
}

class ReadVtu : public ::testing::TestWithParam<core::VtuEncoding> {};

TEST_P(ReadVtu, ReadsBackWhatRunWrites) {
  // A T6 cantilever: points, cells and the smoothed stresses round-trip through the VTU, exactly
  // through raw binary arrays, to 12 significant digits through ASCII.
  const bool ascii = GetParam() == core::VtuEncoding::kAscii;
  const double digits = ascii ? 1e-11 : 0.0;
  const core::Scene scene = core::load_scene(std::string(C2D_SOURCE_DIR) + "/examples/cantilever.toml",
                                             {"body.beam.mesh.size=0.2"});
  const core::Model model = core::build_model(scene);
  const core::Results r = nonlinear::solve_linear_static(model, scene.analysis);
  const auto path = std::filesystem::temp_directory_path() / "c2d_read_vtu.vtu";
  core::write_file_atomic(path.string(), core::vtu_document(model, r, GetParam()));
  const app::VtuData v = app::read_vtu(path.string());
  EXPECT_EQ(v.order, 2);
  ASSERT_EQ(v.points.size(), static_cast<size_t>(model.mesh.num_nodes()));
  ASSERT_EQ(v.cells.size(), static_cast<size_t>(model.mesh.num_elements()));
  for (int e = 0; e < model.mesh.num_elements(); ++e)
    for (int i = 0; i < 6; ++i) ASSERT_EQ(v.cells[e][i], model.mesh.elements[e][i]);
  const auto& s = v.point_data.at("stress_smoothed");
  const auto& vm = v.point_data.at("von_mises_smoothed");
  const auto& u = v.point_data.at("displacement");
  const double scale = r.nodal_stress.cwiseAbs().maxCoeff();
  for (int n = 0; n < model.mesh.num_nodes(); ++n) {
    EXPECT_NEAR((v.points[n] - model.mesh.nodes[n]).norm(), 0.0, 1e-11 * ascii);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(s[3 * n + c], r.nodal_stress(c, n), digits * scale);
    for (int c = 0; c < 2; ++c)
      EXPECT_NEAR(u[3 * n + c], r.displacement[2 * n + c], digits * r.displacement.cwiseAbs().maxCoeff());
    EXPECT_NEAR(vm[n], core::nodal_quantity(model, r, "vm", n), digits * scale);
  }
  EXPECT_EQ(v.cell_data.at("zz_local_parameter").size(), v.cells.size());
  EXPECT_EQ(v.components.at("stress_element"), 3);
  // A file that is not one: the error names it.
  core::write_file_atomic(path.string(), "<VTKFile></VTKFile>\n");
  try {
    app::read_vtu(path.string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string() + ": expected a VTK UnstructuredGrid"),
              std::string::npos) << e.what();
  }
  // A binary file cut short: the array that runs past the end is named.
  if (!ascii) {
    std::string doc = core::vtu_document(model, r, GetParam());
    doc.resize(doc.size() - 1000);
    core::write_file_atomic(path.string(), doc);
    try {
      app::read_vtu(path.string());
      FAIL() << "no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("DataArray 'material_id': expected"), std::string::npos)
          << e.what();
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Encodings, ReadVtu,
                         ::testing::Values(core::VtuEncoding::kBinary, core::VtuEncoding::kAscii),
                         [](const auto& info) {
                           return info.param == core::VtuEncoding::kAscii ? "Ascii" : "Binary";
                         });

TEST(Gnuplot, ChartLeavesOnlyItsPicturesInTheFolder) {
  // Issue 16, finding 7: a chart's data and script are made in a private temporary folder, so
  // an interrupted chart leaves no intermediate in the output folder, and a finished one leaves
  // exactly STEM.png and STEM.svg (the PNG a valid image) and nothing in the temporary folder.
  namespace fs = std::filesystem;
  const fs::path root = fs::temp_directory_path() / ("c2d_plot_" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "tmp");
  fs::create_directories(root / "out");
  const char* old = std::getenv("TMPDIR");
  const std::string saved = old ? old : "";
  ::setenv("TMPDIR", (root / "tmp").c_str(), 1);
  const std::string dir = (root / "out").string();
  const std::string err = app::plot_with_data(
      dir, "line", "plot " + app::gp_file(dir + "/line.dat") + " using 1:2 with lines\n",
      {{dir + "/line.dat", "0 0\n1 1\n2 4\n"}});
  if (old) ::setenv("TMPDIR", saved.c_str(), 1); else ::unsetenv("TMPDIR");
  if (err.find("gnuplot") != std::string::npos && err.find("not found") != std::string::npos)
    GTEST_SKIP() << err;
  ASSERT_EQ(err, "");
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(root / "out")) names.push_back(e.path().filename());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"line.png", "line.svg"}));
  std::ifstream png(root / "out" / "line.png", std::ios::binary);
  char magic[4] = {};
  png.read(magic, 4);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  EXPECT_TRUE(fs::is_empty(root / "tmp"));
  fs::remove_all(root);
}
