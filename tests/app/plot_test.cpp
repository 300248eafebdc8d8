// The post-processor's geometry: isoband clipping and reading back the VTU that run writes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/report/field_plot.hpp"
#include "app/report/gnuplot.hpp"
#include "app/report/units.hpp"
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

// Issue 35, item 3: names from data are drawn as written. gnuplot's enhanced text would draw
// `p_max` as p with a subscript m followed by "ax"; gp_text escapes the markup characters with
// a backslash (which inside single quotes gnuplot reads as the escape) and still doubles quotes.
TEST(Gnuplot, TextFromDataIsEscapedForEnhancedTextAndQuoting) {
  EXPECT_EQ(app::gp_text("p_max"), "'p\\_max'");
  EXPECT_EQ(app::gp_text("a^2 {b} @c &d ~e"), "'a\\^2 \\{b\\} \\@c \\&d \\~e'");
  EXPECT_EQ(app::gp_text("it's C:\\tmp"), "'it''s C:\\\\tmp'");
  EXPECT_EQ(app::gp_text("line\nbreak"), "'line break'");
}

// Issue 35, items 1 and 7: one perceptually uniform palette (viridis' control points, dark
// purple to yellow) and the same font, line width and background in the PNG and the SVG (the
// SVG's font scaled by 96/72: cairo sizes fonts in points at 96 dpi, the SVG in pixels).
TEST(Gnuplot, ViridisPaletteAndOneStyleForPngAndSvg) {
  const std::string palette = app::gp_palette(9);
  EXPECT_EQ(palette.rfind("set palette defined (0 '#440154', ", 0), 0u) << palette;
  EXPECT_NE(palette.find("4 '#21908d'"), std::string::npos) << palette;
  EXPECT_NE(palette.find("8 '#fde725') maxcolors 9\n"), std::string::npos) << palette;
  EXPECT_EQ(app::gp_palette().find("maxcolors"), std::string::npos);
  const std::string png = app::gp_terminal("png"), svg = app::gp_terminal("svg");
  EXPECT_EQ(png, "set terminal pngcairo size 1200,800 enhanced font 'Sans,11' linewidth 1\n");
  EXPECT_EQ(svg,
            "set terminal svg size 1200,800 enhanced font 'Sans,11' linewidth 1 fontscale 1.3333 "
            "background rgb 'white'\n");
}

// Issue 35, item 1: colour bars tick at round numbers (1, 2, 2.5 or 5 times 10^k), their range
// the data's widened to whole ticks, bands dividing the tick intervals evenly.
TEST(FieldPlot, ColourBarTicksAreRoundNumbers) {
  EXPECT_DOUBLE_EQ(app::nice_step(36.0), 50.0);
  EXPECT_DOUBLE_EQ(app::nice_step(2.1), 2.5);
  EXPECT_DOUBLE_EQ(app::nice_step(1.0), 1.0);
  EXPECT_DOUBLE_EQ(app::nice_step(0.00031), 0.0005);
  // hertz_rigid_fast's contact zone: von Mises 0.419608 to 216.434 MPa.
  const app::ColourScale vm = app::colour_scale(0.419608, 216.434, 12);
  EXPECT_DOUBLE_EQ(vm.lo, 0.0);
  EXPECT_DOUBLE_EQ(vm.hi, 225.0);
  EXPECT_DOUBLE_EQ(vm.tick, 25.0);
  EXPECT_EQ(vm.bands, 9);
  // Its u_x: -0.0034006 to 0.0012237 mm.
  const app::ColourScale ux = app::colour_scale(-0.0034006, 0.0012237, 12);
  EXPECT_NEAR(ux.lo, -0.0035, 1e-15);
  EXPECT_NEAR(ux.hi, 0.0015, 1e-15);
  EXPECT_NEAR(ux.tick, 0.0005, 1e-15);
  EXPECT_EQ(ux.bands, 10);
  // Few ticks, more bands asked: each tick interval cut in equal bands.
  const app::ColourScale fine = app::colour_scale(0.0, 4.0, 20);
  EXPECT_DOUBLE_EQ(fine.tick, 0.5);
  EXPECT_EQ(fine.bands, 16);
  EXPECT_DOUBLE_EQ(fine.band, 0.25);
}

// Issue 35, items 2 and 5: numbers in titles to 3 significant digits with their unit; the
// deformation at true scale for finite strain and never shrunk, else a round magnification.
TEST(FieldPlot, TitlesRoundAndStateTheDeformation) {
  EXPECT_EQ(app::rounded_text(0.739397), "0.739");
  EXPECT_EQ(app::rounded_text(213.528), "214");
  EXPECT_EQ(app::rounded_text(2000.0), "2000");
  EXPECT_EQ(app::rounded_text(1.5e-5), "1.5e-05");
  EXPECT_EQ(app::rounded_text(-382.02), "-382");
  EXPECT_EQ(app::quantity_text(213.528, "MPa"), "214 MPa");
  EXPECT_EQ(app::quantity_text(213.528, ""), "214");
  // 8 % of a 100-long model over a largest displacement of 0.01 is 800: drawn at 500.
  EXPECT_DOUBLE_EQ(app::displacement_scale(0.01, 100.0, false), 500.0);
  EXPECT_DOUBLE_EQ(app::displacement_scale(0.02208, 1000.0, false), 2000.0);
  // elastica: a tip deflection of 493 on a 1000-long beam is drawn as it is, never shrunk.
  EXPECT_DOUBLE_EQ(app::displacement_scale(493.4, 1000.0, false), 1.0);
  EXPECT_DOUBLE_EQ(app::displacement_scale(1e-3, 1000.0, true), 1.0);
  EXPECT_DOUBLE_EQ(app::displacement_scale(0.0, 1000.0, false), 0.0);
  EXPECT_EQ(app::deformation_text(1.0), "true scale");
  EXPECT_EQ(app::deformation_text(2000.0), "displacements ×2000");
}

// A picture drawn end to end: the title says the rounded range with its unit and the name as
// written (an unescaped p_max would split into tspans p, m, ax), the colour bar ticks round.
TEST(FieldPlot, PictureTitleAndColourBarAsAReaderReadsThem) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("c2d_plot_title_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  app::VtuData v;
  v.points = {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1)};
  v.cells = {{0, 1, 2, 0, 0, 0}};
  v.point_data["von_mises_smoothed"] = {0.739397, 213.528, 100.0};
  v.components["von_mises_smoothed"] = 1;
  v.point_data["displacement"] = {0, 0, 0.01, 0, 0, 0.02};
  v.components["displacement"] = 2;
  app::PlotOptions o;
  o.title = "p_max field";
  o.units = "N, mm, MPa";
  o.deformed = 1.0;
  const app::PlotSummary s = app::plot_field(v, o, dir.string(), "vm");
  if (s.error.find("not found") != std::string::npos) GTEST_SKIP() << s.error;
  ASSERT_EQ(s.error, "");
  std::ifstream in(dir / "vm.svg");
  std::stringstream text;
  text << in.rdbuf();
  const std::string svg = text.str();
  EXPECT_NE(svg.find(">p_max field: 0.739 to 214 MPa, true scale</tspan>"), std::string::npos)
      << svg.substr(0, 4000);
  EXPECT_EQ(svg.find("0.739397"), std::string::npos);
  EXPECT_NE(svg.find(">225</tspan>"), std::string::npos) << "the colour bar ends at a tick";
  EXPECT_NE(svg.find(">vm [MPa]</tspan>"), std::string::npos);
  fs::remove_all(dir);
}
