// Detection: projections onto linear and quadratic edges, sliding across edges, corners,
// circle obstacles, and the bucket-grid search against brute force.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "constraints/contact_detection.hpp"

using namespace c2d;
using namespace c2d::constraints;

TEST(Detection, LinearEdgeGapAndNormal) {
  // Edge (0,0) -> (2,0): the body lies on its left (above), the outward normal is (0, -1).
  const std::vector<Vec2> x = {{0, 0}, {2, 0}};
  MasterEdge e;
  e.nodes = {0, 1, -1};
  const auto out = project_on_edge(e, x, Vec2(0.5, -0.3));
  EXPECT_NEAR(out.gap, 0.3, 1e-15);
  EXPECT_NEAR(out.xi, 0.25, 1e-15);
  EXPECT_NEAR(out.normal.y(), -1.0, 1e-15);
  EXPECT_NEAR(out.weights[0], 0.75, 1e-15);
  const auto inside = project_on_edge(e, x, Vec2(1.5, 0.1));
  EXPECT_NEAR(inside.gap, -0.1, 1e-15);  // penetration is a negative gap
}

TEST(Detection, QuadraticEdgeFollowsItsParabola) {
  // Nodes (-1,1), (1,1) and middle (0,0) interpolate y = x² exactly. A point at distance 0.1
  // along the outward normal of x = 0.5 must project back to x = 0.5 (xi = 0.75), gap 0.1.
  const std::vector<Vec2> x = {{-1, 1}, {1, 1}, {0, 0}};
  MasterEdge e;
  e.nodes = {0, 1, 2};
  e.count = 3;
  const Vec2 foot(0.5, 0.25), normal = Vec2(1, -1).normalized();
  const auto out = project_on_edge(e, x, foot + 0.1 * normal);
  EXPECT_NEAR(out.xi, 0.75, 1e-12);
  EXPECT_NEAR(out.gap, 0.1, 1e-12);
  EXPECT_NEAR((out.normal - normal).norm(), 0.0, 1e-12);
  EXPECT_NEAR(out.weights[0] + out.weights[1] + out.weights[2], 1.0, 1e-15);
  const auto inside = project_on_edge(e, x, foot - 0.05 * normal);
  EXPECT_NEAR(inside.gap, -0.05, 1e-12);
}

TEST(Detection, SlidingAcrossEdgesKeepsTheGapContinuous) {
  const std::vector<Vec2> x = {{0, 0}, {1, 0}, {2, 0}};
  std::vector<MasterEdge> edges(2);
  edges[0].nodes = {0, 1, -1};
  edges[1].nodes = {1, 2, -1};
  const MasterSurfaceSearch search(edges, x, 0.5);
  int last_edge = -1;
  for (double px : {0.9, 0.99, 1.0, 1.01, 1.1}) {
    const auto q = search.project(Vec2(px, -0.05));
    ASSERT_TRUE(q.found);
    EXPECT_NEAR(q.gap, 0.05, 1e-14) << px;
    EXPECT_NEAR(q.normal.y(), -1.0, 1e-14) << px;
    EXPECT_NEAR(q.point.x(), px, 1e-14);
    last_edge = q.vertex >= 0 ? last_edge : q.edge;
  }
  EXPECT_EQ(last_edge, 1);  // the node slid onto the second edge
}

TEST(Detection, NodeFacingAConvexCorner) {
  // Unit square, counter-clockwise: bottom edge normal (0,-1), right edge normal (1,0).
  const std::vector<Vec2> x = {{0, 0}, {1, 0}, {1, 1}};
  std::vector<MasterEdge> edges(2);
  edges[0].nodes = {0, 1, -1};
  edges[1].nodes = {1, 2, -1};
  const MasterSurfaceSearch search(edges, x, 2.0);
  const auto q = search.project(Vec2(1.3, -0.4));
  ASSERT_TRUE(q.found);
  EXPECT_EQ(q.vertex, 1);
  EXPECT_NEAR(q.gap, 0.5, 1e-14);
  EXPECT_NEAR(q.normal.x(), 0.6, 1e-14);
  EXPECT_NEAR(q.normal.y(), -0.8, 1e-14);
  // Just inside the corner along its bisector: the mean normal, a negative gap.
  const auto in = search.project(Vec2(1.0 - 0.01, 0.01) + Vec2(0.0, -0.0));
  ASSERT_TRUE(in.found);
  EXPECT_LT(in.gap, 0.0);
}

TEST(Detection, PointBesideAFreeEndOfTheMasterIsOutside) {
  // A master surface that ends (a punch's bottom face, normal (0,-1), from (0,0) to (1,0); the
  // punch is above it). A slave point beside the end, level with the face or slightly above it,
  // is beside the punch, not under it: gap = its distance from the end, normal from the end
  // toward it (before, the mean-normal branch gave it gap 0 or a penetration, and a punch on an
  // elastic foundation lost 7 % of its load to such fictitious rows).
  const std::vector<Vec2> x = {{0, 0}, {1, 0}};
  std::vector<MasterEdge> edges(1);
  edges[0].nodes = {0, 1, -1};
  const MasterSurfaceSearch search(edges, x, 2.0);
  const auto level = search.project(Vec2(1.25, 0.0));
  ASSERT_TRUE(level.found);
  EXPECT_EQ(level.vertex, 1);
  EXPECT_NEAR(level.gap, 0.25, 1e-14);
  EXPECT_NEAR(level.normal.x(), 1.0, 1e-14);
  const auto above = search.project(Vec2(1.3, 0.4));
  EXPECT_NEAR(above.gap, 0.5, 1e-14);
  EXPECT_NEAR(above.normal.x(), 0.6, 1e-14);
  EXPECT_NEAR(above.normal.y(), 0.8, 1e-14);
  // Under the face the edge itself answers: penetration 0.1 at x = 0.5.
  const auto under = search.project(Vec2(0.5, 0.1));
  EXPECT_EQ(under.vertex, -1);
  EXPECT_NEAR(under.gap, -0.1, 1e-14);
  // Just past the end (within a tenth of the end edge) the face continues as a parabola falling
  // away by 0.1 over 0.1: a slave that sank there is held, never released. At x = 1.03 the
  // rounded face lies 0.03²/0.1 = 0.009 above the face's line, so a point 0.01 above the line
  // penetrates by 0.001 (the punch is above; y grows into it).
  const auto sunk = search.project(Vec2(1.03, 0.01));
  ASSERT_TRUE(sunk.found);
  EXPECT_FALSE(sunk.beyond_free_end);
  EXPECT_NEAR(sunk.gap, -0.001, 1e-14);
  EXPECT_NEAR(sunk.normal.x(), 0.6 / std::sqrt(1.36), 1e-14);  // ∝ (0, −1) + 2·0.03/0.1·(1, 0)
  // The gap is continuous across the band's end for points on the face's line.
  const auto inside_band = search.project(Vec2(1.1 - 1e-12, 0.0));
  EXPECT_NEAR(inside_band.gap, 0.1, 1e-10);
  EXPECT_TRUE(level.beyond_free_end);
  EXPECT_TRUE(above.beyond_free_end);
}

TEST(Detection, CircleObstaclesOutsideAndInside) {
  Obstacle disk;
  disk.type = Obstacle::Type::kCircle;
  disk.center = Vec2(0, 0);
  disk.radius = 1.0;
  double g;
  Vec2 n;
  disk.gap(Vec2(0, 1.5), g, n);
  EXPECT_NEAR(g, 0.5, 1e-15);
  EXPECT_NEAR(n.y(), 1.0, 1e-15);
  disk.gap(Vec2(0.6, 0.6), g, n);
  EXPECT_NEAR(g, std::sqrt(0.72) - 1.0, 1e-15);  // penetrating
  Obstacle hole = disk;
  hole.inside = true;
  hole.gap(Vec2(0, 0.5), g, n);
  EXPECT_NEAR(g, 0.5, 1e-15);
  EXPECT_NEAR(n.y(), -1.0, 1e-15);  // free direction: toward the centre
  Obstacle line;
  line.point = Vec2(0, 2);
  line.normal = Vec2(0, 1);
  line.gap(Vec2(3, 1.75), g, n);
  EXPECT_NEAR(g, -0.25, 1e-15);
}

TEST(Detection, GridSearchEqualsBruteForceOnACurvedSurface) {
  // 200 quadratic edges on a circle of radius 10 (body inside: counter-clockwise), 2000 random
  // points in a ring around it: the grid must find the same closest distance as a full scan.
  std::vector<Vec2> x;
  std::vector<MasterEdge> edges;
  const int ne = 200;
  for (int i = 0; i < 2 * ne; ++i) {
    const double t = 2 * M_PI * i / (2 * ne);
    x.emplace_back(10 * std::cos(t), 10 * std::sin(t));
  }
  for (int k = 0; k < ne; ++k) {
    MasterEdge e;
    e.nodes = {2 * k, (2 * k + 2) % (2 * ne), 2 * k + 1};
    e.count = 3;
    edges.push_back(e);
  }
  const double search = 0.8;
  const MasterSurfaceSearch grid(edges, x, search);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ang(0, 2 * M_PI), rad(9.5, 10.5);
  int compared = 0;
  for (int k = 0; k < 2000; ++k) {
    const double t = ang(rng), r = rad(rng);
    const Vec2 p(r * std::cos(t), r * std::sin(t));
    double brute = 1e300;
    for (const auto& e : edges) brute = std::min(brute, (project_on_edge(e, x, p).point - p).norm());
    const auto q = grid.project(p);
    ASSERT_TRUE(q.found);
    EXPECT_NEAR((q.point - p).norm(), brute, 1e-12);
    // The quadratic edges approximate the circle to ~1e-5: the gap is r − 10.
    EXPECT_NEAR(q.gap, r - 10.0, 2e-4);
    ++compared;
  }
  EXPECT_EQ(compared, 2000);
}
