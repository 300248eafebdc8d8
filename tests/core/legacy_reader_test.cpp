// The seed program's data format: the bundled V1 file and the equivalent TOML scene (same mesh
// through a Gmsh .msh file) give the same displacements; malformed files are named by line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <tuple>

#include "core/errors.hpp"
#include "core/model.hpp"
#include "core/scene.hpp"
#include "nonlinear/load_stepper.hpp"

using namespace c2d;
using namespace c2d::core;

namespace {
std::string example(const char* name) { return std::string(C2D_SOURCE_DIR) + "/examples/" + name; }

std::string write_temp(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << text;
  return path.string();
}
}  // namespace

TEST(LegacyReader, SameDisplacementsAsTomlScene) {
  const Scene dat = load_scene(example("legacy/v1_beam.dat"));
  const Scene toml = load_scene(example("legacy/v1_beam.toml"));
  const Model md = build_model(dat), mt = build_model(toml);
  const Results rd = c2d::nonlinear::solve_linear_static(md, dat.analysis);
  const Results rt = c2d::nonlinear::solve_linear_static(mt, toml.analysis);
  ASSERT_EQ(rd.status, SolveStatus::kConverged);
  ASSERT_EQ(rt.status, SolveStatus::kConverged);
  ASSERT_EQ(md.mesh.num_nodes(), mt.mesh.num_nodes());
  const double scale = rd.displacement.cwiseAbs().maxCoeff();
  EXPECT_GT(scale, 1e-4);
  // Node numbering differs (gmsh tags are compacted): match nodes by coordinates.
  for (int i = 0; i < md.mesh.num_nodes(); ++i)
    for (int j = 0; j < mt.mesh.num_nodes(); ++j)
      if ((md.mesh.nodes[i] - mt.mesh.nodes[j]).norm() < 1e-12) {
        EXPECT_LT((rd.displacement.segment<2>(2 * i) - rt.displacement.segment<2>(2 * j)).norm(),
                  1e-12 * scale);
      }
  // The tip deflection of the seed's table: -0.0002 (printed to 4 decimals).
  EXPECT_NEAR(rd.displacement[2 * 5 + 1], -0.0002, 0.5e-4);
}

TEST(LegacyReader, PrescribedDisplacementFromSupportedLoadColumn) {
  // sx = 1 with fx = 0.001: the seed's big-number trick prescribed u = 0.001; here it is an
  // eliminated Dirichlet value.
  const std::string path = write_temp("c2d_prescribed.dat", R"(4 2 1
1 0 0 1 1 0 0
2 1 0 1 0 0.001 0
3 1 1 1 0 0.001 0
4 0 1 1 0 0 0
1 1 2 3 0 1000 1 0
2 1 3 4 0 1000 1 0
1e20 1e20
)");
  const Scene s = load_scene(path);
  const Model m = build_model(s);
  const Results r = c2d::nonlinear::solve_linear_static(m, s.analysis);
  ASSERT_EQ(r.status, SolveStatus::kConverged);
  // Uniaxial stretch eps_x = 0.001 with nu = 0: sx = E eps = 1, uniform.
  for (int e = 0; e < 2; ++e) EXPECT_NEAR(r.element_stresses.at_points[e](0, 0), 1.0, 1e-12);
  EXPECT_NEAR(r.displacement[2 * 1], 0.001, 1e-15);
}

TEST(LegacyReader, ErrorsNameTheLine) {
  const std::string path = write_temp("c2d_bad.dat", "3 1 1\n1 0 0 1 1 0 0\n2 1 0 0 0\n");
  try {
    load_scene(path);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("c2d_bad.dat:3: expected 7 numbers"), std::string::npos)
        << e.what();
  }
}

TEST(LegacyReader, GapElementsAreReadAsNodePairs) {
  const std::string path = write_temp("c2d_gap.dat", R"(4 3 1
1 0 0 1 1 0 0
2 1 0 0 0 0 0
3 1 1 0 0 0 0
4 0 1 1 1 0 0
1 1 2 3 0 1000 1 0.3
2 1 3 4 0 1000 1 0.3
3 2 3 0 1 0 1 1e6
1e20 1e20
)");
  const Scene s = load_scene(path);
  ASSERT_EQ(s.explicit_model->gaps.size(), 1u);
  EXPECT_EQ(s.explicit_model->gaps[0].node_a, 1);
  EXPECT_EQ(s.explicit_model->gaps[0].node_b, 2);
  EXPECT_DOUBLE_EQ(s.explicit_model->gaps[0].stiffness, 1e6);
  EXPECT_EQ(build_model(s).mesh.num_elements(), 2);  // gaps are constraints, not elements
}

TEST(LegacyReader, DegenerateGapElementsAreRefusedAtTheirLine) {
  // Issue 16, finding 5: zero or negative stiffness and a gap from a node to itself.
  const std::string head = "4 3 1\n1 0 0 1 1 0 0\n2 1 0 0 0 0 0\n3 1 1 0 0 0 0\n4 0 1 1 1 0 0\n"
                           "1 1 2 3 0 1000 1 0.3\n2 1 3 4 0 1000 1 0.3\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"3 2 3 0 1 0 1 0\n", "a stiffness k > 0"},
      {"3 2 3 0 1 0 1 -5\n", "a stiffness k > 0"},
      {"3 2 2 0 1 0 1 1e6\n", "from a node to itself"},
  };
  for (const auto& [line, expected] : cases) {
    const std::string path = write_temp("c2d_bad_gap.dat", head + line + "1e20 1e20\n");
    try {
      load_scene(path);
      ADD_FAILURE() << line << ": expected an InputError";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("c2d_bad_gap.dat:8:"), std::string::npos) << msg;
      EXPECT_NE(msg.find(expected), std::string::npos) << msg;
    }
  }
}

TEST(LegacyReader, NonFiniteAndDegenerateInputIsRefusedAtItsLine) {
  // Issue 16, finding 6: NaN coordinates, E = inf, a repeated node and a zero-area element used
  // to end as "singular" (or reach the output); each is now a located input error.
  const std::string nodes = "1 0 0 1 1 0 0\n2 1 0 0 0 0 0\n3 1 1 0 0 0 0\n4 0 1 1 1 0 0\n";
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {"4 1 1\n1 0 0 1 1 0 0\n2 nan 0 0 0 0 0\n3 1 1 0 0 0 0\n4 0 1 1 1 0 0\n1 1 2 3 0 1000 1 0.3\n",
       ":3:", "finite numbers on a node line"},
      {"4 1 1\n" + nodes + "1 1 2 3 0 inf 1 0.3\n", ":6:", "E and thickness in [1e-30, 1e30]"},
      {"4 1 1\n" + nodes + "1 1 2 3 0 1e308 1 0.3\n", ":6:", "E and thickness in [1e-30, 1e30]"},
      {"4 1 1\n" + nodes + "1 1 2 2 0 1000 1 0.3\n", ":6:", "found node 2 twice"},
      {"4 1 1\n1 0 0 1 1 0 0\n2 1 0 0 0 0 0\n3 2 0 0 0 0 0\n4 0 1 1 1 0 0\n1 1 2 3 0 1000 1 0.3\n",
       ":6:", "collinear corner nodes 1, 2, 3"},
  };
  for (const auto& [text, line, expected] : cases) {
    const std::string path = write_temp("c2d_bad_element.dat", text + "1e20 1e20\n");
    try {
      load_scene(path);
      ADD_FAILURE() << expected << ": expected an InputError";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("c2d_bad_element.dat" + line), std::string::npos) << msg;
      EXPECT_NE(msg.find(expected), std::string::npos) << msg;
    }
  }
}

// Issue 16 (findings 4 and 8, and a UBSan finding of the fuzzer): counts beyond int, or beyond
// what the file can hold, and element types that are not 0, 1 or 2 are refused at their line
// before anything is converted or sized by them.
TEST(LegacyReader, HugeCountsAndTypesAreRefusedBeforeUse) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"1e115 1 1\n1 0 0 1 1 0 0\n", "c2d_huge1.dat:1: expected positive integer node and element counts"},
      {"200000000 1 1\n1 0 0 1 1 0 0\n", "c2d_huge2.dat:1: expected node and element counts that"},
      {"3 1 1\n1 0 0 1 1 0 0\n2 1 0 0 0 0 0\n3 0 1 0 0 0 0\n1 1 2 3 7e300 1 1 0.3\n",
       "c2d_huge3.dat:5: expected element type 0 (plane stress), 1 (gap) or 2 (plane strain)"},
  };
  int k = 0;
  for (const auto& [text, expect] : cases) {
    const std::string path = write_temp("c2d_huge" + std::to_string(++k) + ".dat", text);
    try {
      load_scene(path);
      ADD_FAILURE() << "expected an InputError for " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << e.what();
    }
  }
}
