// Point-cloud meshing (the seed's pre-processor): the triangulation uses exactly the given
// points, is Delaunay, respects a given boundary, rejects degenerate clouds, and is a body like
// any other (a patch test on it).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <sstream>

#include "core/errors.hpp"
#include "core/model.hpp"
#include "core/scene.hpp"
#include "nonlinear/load_stepper.hpp"

using namespace c2d;

namespace {

std::string cloud_scene(const std::vector<Vec2>& points, const std::vector<Vec2>& boundary = {},
                        const char* element = "T3") {
  std::ostringstream os;
  os.precision(17);
  auto list = [&](const std::vector<Vec2>& v) {
    os << "[";
    for (size_t i = 0; i < v.size(); ++i) os << (i ? ", " : "") << "[" << v[i].x() << ", " << v[i].y() << "]";
    os << "]";
  };
  os << "[analysis]\nkind = \"plane_stress\"\nelement = \"" << element << "\"\n"
     << "[[material]]\nname = \"m\"\nE = 1000.0\nnu = 0.25\n"
     << "[[body]]\nname = \"cloud\"\nmaterial = \"m\"\nshape = { type = \"points\", points = ";
  list(points);
  if (!boundary.empty()) {
    os << ", boundary = ";
    list(boundary);
  }
  os << " }\n";
  return os.str();
}

core::Mesh mesh_of(const std::string& text) {
  return core::build_model(core::parse_scene(text, "cloud.toml")).mesh;
}

}  // namespace

TEST(PointCloud, SquareWithItsCentreGivesFourTriangles) {
  // The known triangulation: the centre joined to the four corners, nothing added.
  const core::Mesh m = mesh_of(cloud_scene({{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0.5}}));
  ASSERT_EQ(m.num_nodes(), 5);
  ASSERT_EQ(m.num_elements(), 4);
  int centre = -1;
  for (int n = 0; n < 5; ++n)
    if ((m.nodes[n] - Vec2(0.5, 0.5)).norm() < 1e-15) centre = n;
  ASSERT_GE(centre, 0);
  for (const auto& e : m.elements) EXPECT_TRUE(e[0] == centre || e[1] == centre || e[2] == centre);
  EXPECT_EQ(m.boundary_edges.size(), 4u);
  // A 3 x 3 grid: 9 points, 8 triangles (the grid's co-circular squares may split either way).
  std::vector<Vec2> grid;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) grid.emplace_back(0.5 * i, 0.5 * j);
  const core::Mesh g = mesh_of(cloud_scene(grid));
  EXPECT_EQ(g.num_nodes(), 9);
  EXPECT_EQ(g.num_elements(), 8);
}

TEST(PointCloud, RandomCloudIsItsDelaunayTriangulation) {
  // 300 random points in the unit square: every point a vertex and no other, 2n − h − 2
  // triangles (h hull vertices, Euler), no overlap (the areas sum to the hull's area, 1e-12),
  // the Delaunay property on every interior edge (the two angles opposite it sum to at most π,
  // 1e-9 slack), and the quality report names the slivers a random cloud produces.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec2> pts;
  for (int i = 0; i < 300; ++i) pts.emplace_back(u(rng), u(rng));
  const core::Mesh m = mesh_of(cloud_scene(pts));
  ASSERT_EQ(m.num_nodes(), 300);
  for (const auto& p : pts) {
    double nearest = 1e300;
    for (const auto& n : m.nodes) nearest = std::min(nearest, (n - p).norm());
    EXPECT_LT(nearest, 1e-14);
  }
  const int hull = static_cast<int>(m.boundary_edges.size());
  EXPECT_EQ(m.num_elements(), 2 * 300 - hull - 2);
  double area = 0.0, hull_area = 0.0;
  for (const auto& e : m.elements) {
    const Vec2 a = m.nodes[e[0]], b = m.nodes[e[1]], c = m.nodes[e[2]];
    const double signed_area = 0.5 * ((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
    EXPECT_GT(signed_area, 0.0);
    area += signed_area;
  }
  for (const auto& be : m.boundary_edges) {
    const Vec2 a = m.nodes[be.nodes[0]], b = m.nodes[be.nodes[1]];
    hull_area += 0.5 * (a.x() * b.y() - a.y() * b.x());
  }
  EXPECT_NEAR(area, std::abs(hull_area), 1e-12);
  std::map<std::pair<int, int>, std::vector<int>> opposite;  // edge -> opposite vertices
  for (const auto& e : m.elements)
    for (int k = 0; k < 3; ++k) {
      const int a = e[(k + 1) % 3], b = e[(k + 2) % 3];
      opposite[{std::min(a, b), std::max(a, b)}].push_back(e[k]);
    }
  auto angle = [&](int at, int a, int b) {
    const Vec2 u = m.nodes[a] - m.nodes[at], v = m.nodes[b] - m.nodes[at];
    return std::atan2(std::abs(u.x() * v.y() - u.y() * v.x()), u.dot(v));
  };
  int interior = 0;
  for (const auto& [edge, opp] : opposite) {
    if (opp.size() != 2) continue;
    ++interior;
    EXPECT_LE(angle(opp[0], edge.first, edge.second) + angle(opp[1], edge.first, edge.second),
              M_PI + 1e-9);
  }
  EXPECT_EQ(interior, (3 * m.num_elements() - hull) / 2);
  const auto [min_angle, skinny] = m.angle_quality();
  EXPECT_GT(skinny, 0);
  EXPECT_LT(min_angle, 15.0);
}

TEST(PointCloud, NonConvexBoundaryIsRespected) {
  // An L-shaped boundary with interior points: no triangle outside the L (centroids tested),
  // area exactly 3.
  const std::vector<Vec2> l = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  const std::vector<Vec2> pts = {{0.5, 0.5}, {1.5, 0.5}, {0.5, 1.5}, {1.0, 0.5}, {0.5, 1.0}};
  const core::Mesh m = mesh_of(cloud_scene(pts, l));
  double area = 0.0;
  for (const auto& e : m.elements) {
    const Vec2 a = m.nodes[e[0]], b = m.nodes[e[1]], c = m.nodes[e[2]];
    area += 0.5 * std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
    const Vec2 g = (a + b + c) / 3.0;
    EXPECT_FALSE(g.x() > 1.0 && g.y() > 1.0) << g.transpose();
  }
  EXPECT_NEAR(area, 3.0, 1e-12);
  EXPECT_EQ(m.num_nodes(), 11);
}

TEST(PointCloud, DegenerateCloudsAreRejectedByName) {
  auto message = [](const std::string& text) {
    try {
      mesh_of(text);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(cloud_scene({{0, 0}, {1, 0}, {1, 1}, {1, 0}})).find("points 2 and 4 coincide"),
            std::string::npos);
  EXPECT_NE(message(cloud_scene({{0, 0}, {1, 1}, {2, 2}, {3, 3}})).find("collinear"),
            std::string::npos);
  EXPECT_NE(message(cloud_scene({{0.5, 0.5}, {0.25, 0.25}, {3, 0.5}}, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}))
                .find("point 3 (3, 0.5) lies outside the boundary polygon"),
            std::string::npos);
}

TEST(PointCloud, ACloudBodyPassesThePatchTest) {
  // A jittered 6 x 4 cloud over [0, 3] x [0, 2], T6, pulled by 30 N on the right edge, held by
  // rollers on the left and bottom: the uniform stress σx = 30 / (2 × 1) = 15 everywhere
  // (1e-10 relative), as on any mesh.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-0.12, 0.12);
  std::vector<Vec2> pts;
  for (int i = 0; i <= 6; ++i)
    for (int j = 0; j <= 4; ++j) {
      const bool edge = i == 0 || i == 6 || j == 0 || j == 4;
      pts.emplace_back(0.5 * i + (edge ? 0.0 : jitter(rng)), 0.5 * j + (edge ? 0.0 : jitter(rng)));
    }
  std::string text = cloud_scene(pts, {}, "T6");
  text += "[[support]]\non = { line = { point = [0.0, 0.0], direction = [0.0, 1.0] } }\nfix = [\"ux\"]\n"
          "[[support]]\non = { line = { point = [0.0, 0.0], direction = [1.0, 0.0] } }\nfix = [\"uy\"]\n"
          "[[load]]\non = { line = { point = [3.0, 0.0], direction = [0.0, 1.0] } }\n"
          "total_force = [30.0, 0.0]\n";
  const core::Scene scene = core::parse_scene(text, "cloud.toml");
  const core::Model model = core::build_model(scene);
  const core::Results r = c2d::nonlinear::solve_linear_static(model, scene.analysis);
  ASSERT_EQ(r.status, SolveStatus::kConverged) << r.message;
  for (const auto& s : r.element_stresses.at_points) {
    EXPECT_LT((s.row(0).array() - 15.0).abs().maxCoeff(), 1e-10 * 15.0);
    EXPECT_LT(s.row(1).cwiseAbs().maxCoeff(), 1e-10 * 15.0);
    EXPECT_LT(s.row(2).cwiseAbs().maxCoeff(), 1e-10 * 15.0);
  }
}
