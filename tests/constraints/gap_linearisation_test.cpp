// The contact tangent against finite differences, as the element tangents are checked: in
// finite strain every gap row carries the exact gradient of its gap (its terms) and Hessian
// (its curvature). Central differences of the detected gaps must reproduce the terms, and
// central differences of the terms the curvature, on every branch of node-to-segment (edge
// interior, vertex outside and inside, rounded free end; straight and curved edges), on rigid
// obstacles, and on mortar rows (segment ends moving with the master vertices that cut them).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>
#include <string>

#include "constraints/contact_scene.hpp"
#include "constraints/contact_set.hpp"
#include "constraints/gap_linearisation.hpp"
#include "core/model.hpp"
#include "core/scene.hpp"

using namespace c2d;
using namespace c2d::constraints;

namespace {

/// The largest difference between the analytic and the central-difference derivatives of
/// every row, relative to the largest analytic entry (gradient) or curvature entry (Hessian).
struct TangentError {
  double gradient = 0.0, hessian = 0.0;
  int rows = 0;
};

using RowsAt = std::function<std::map<int, GapRow>(const std::vector<Vec2>&)>;

/// Entry (node, component) of a row's terms, 0 when absent.
double term(const GapRow& r, int node, int c) {
  for (const auto& [n, v] : r.terms)
    if (n == node) return v[c];
  return 0.0;
}

TangentError check_rows(const std::vector<Vec2>& x, const RowsAt& rows_at, double h) {
  TangentError e;
  const std::map<int, GapRow> base = rows_at(x);
  for (const auto& [slot, row] : base) {
    ++e.rows;
    EXPECT_EQ(row.curvature.rows(), 2 * static_cast<int>(row.terms.size())) << "slot " << slot;
    double gmax = 1e-300, hmax = 1e-300, gerr = 0.0, herr = 0.0;
    for (int i = 0; i < 2 * static_cast<int>(row.terms.size()); ++i)
      gmax = std::max(gmax, std::abs(row.terms[i / 2].second[i % 2])),
      hmax = std::max(hmax, row.curvature.row(i).cwiseAbs().maxCoeff());
    for (size_t a = 0; a < row.terms.size(); ++a)
      for (int c = 0; c < 2; ++c) {
        std::vector<Vec2> xp = x, xm = x;
        xp[row.terms[a].first][c] += h;
        xm[row.terms[a].first][c] -= h;
        const auto rp = rows_at(xp), rm = rows_at(xm);
        if (!rp.count(slot) || !rm.count(slot)) {
          ADD_FAILURE() << "slot " << slot << " lost";
          return e;
        }
        const GapRow &p = rp.at(slot), &m = rm.at(slot);
        gerr = std::max(gerr, std::abs((p.gap - m.gap) / (2 * h) - row.terms[a].second[c]));
        for (size_t b = 0; b < row.terms.size(); ++b)
          for (int d = 0; d < 2; ++d) {
            const int node = row.terms[b].first;
            const double fd = (term(p, node, d) - term(m, node, d)) / (2 * h);
            herr = std::max(herr, std::abs(fd - row.curvature(2 * b + d, 2 * a + c)));
          }
      }
    e.gradient = std::max(e.gradient, gerr / gmax);
    e.hessian = std::max(e.hessian, herr / hmax);
  }
  return e;
}

// --- node-to-segment branches on a hand-made master surface --------------------------------

/// A master surface of three edges with its body below: a bent polyline (linear) or arcs
/// (quadratic, middle nodes lifted), free at both ends.
struct Surface {
  std::vector<Vec2> x;
  std::vector<MasterEdge> edges;
};

Surface bent_surface(bool quadratic) {
  Surface s;
  // Corner nodes 0..3 from right to left (body on the left of each edge's direction = below).
  s.x = {{3.0, 0.2}, {2.0, 0.0}, {1.0, 0.1}, {0.0, -0.1}};
  for (int k = 0; k < 3; ++k) {
    MasterEdge e;
    e.nodes = {k, k + 1, -1};
    e.count = 2;
    if (quadratic) {
      const Vec2 mid = 0.5 * (s.x[k] + s.x[k + 1]) + Vec2(0.0, 0.05 * (k % 2 ? 1 : -1));
      e.nodes[2] = static_cast<int>(s.x.size());
      e.count = 3;
      s.x.push_back(mid);
    }
    s.edges.push_back(e);
  }
  return s;
}

/// Rows of slave nodes (appended to the surface's positions) as node_to_segment detects them.
RowsAt surface_rows(const Surface& s, int first_slave) {
  return [&s, first_slave](const std::vector<Vec2>& x) {
    const MasterSurfaceSearch search(s.edges, x, 5.0);
    std::map<int, GapRow> out;
    for (int k = first_slave; k < static_cast<int>(x.size()); ++k) {
      const SegmentProjection q = search.project(x[k], k);
      if (!q.found) continue;
      GapRow r;
      r.gap = q.gap;
      const LocalGap full = node_segment_gap(search, q, k, Positions{x});
      set_row_derivatives(full, r);
      EXPECT_NEAR(r.gap, full.value, 1e-13) << "node " << k;
      // Without the Hessian (a residual's evaluation): the same value and gradient, to 1e-13.
      const LocalGap first = node_segment_gap(search, q, k, Positions{x}, false);
      EXPECT_NEAR(first.value, full.value, 1e-13) << "node " << k;
      EXPECT_EQ(first.nodes, full.nodes) << "node " << k;
      EXPECT_LT((first.gradient - full.gradient).cwiseAbs().maxCoeff(), 1e-13) << "node " << k;
      EXPECT_EQ(first.hessian.size(), 0) << "node " << k;
      out[k] = r;
    }
    return out;
  };
}

TEST(GapLinearisation, NodeToSegmentBranchesMatchFiniteDifferences) {
  for (bool quadratic : {false, true}) {
    Surface s = bent_surface(quadratic);
    const int first = static_cast<int>(s.x.size());
    // Edge interiors (above and below), a vertex from outside (convex side of node 2 is up?),
    // a vertex from inside, and past both free ends (rounded end; beyond it).
    const std::vector<Vec2> slaves = {{2.4, 0.35}, {1.6, -0.02}, {2.02, 0.6},  {1.0, 0.06},
                                      {3.02, 0.25}, {-0.05, -0.2}, {-0.6, 0.3}, {1.98, -0.01}};
    for (const Vec2& p : slaves) s.x.push_back(p);
    const MasterSurfaceSearch search(s.edges, s.x, 5.0);
    std::map<SegmentProjection::Branch, int> branches;
    for (int k = first; k < static_cast<int>(s.x.size()); ++k) {
      const SegmentProjection q = search.project(s.x[k], k);
      if (q.found) ++branches[q.branch];
    }
    EXPECT_GE(branches.size(), 3u) << "the slaves should visit several branches";
    const TangentError e = check_rows(s.x, surface_rows(s, first), 1e-6);
    EXPECT_EQ(e.rows, static_cast<int>(slaves.size()));
    EXPECT_LT(e.gradient, 1e-7) << (quadratic ? "quadratic" : "linear");
    EXPECT_LT(e.hessian, 1e-6) << (quadratic ? "quadratic" : "linear");
  }
}

// --- whole contact sets: node_to_segment and mortar, T3 and T6, deformable and rigid -------

std::string blocks_scene(const std::string& element, const std::string& detection,
                         bool obstacle) {
  std::string s = R"(
[analysis]
element = ")" + element + R"("
geometric_nonlinearity = true
[[material]]
name = "m"
E = 1000.0
nu = 0.3
[[body]]
name = "low"
material = "m"
shape = { type = "rectangle", min = [0.0, 0.0], max = [2.0, 1.0] }
mesh = { size = 0.37 }
[[body]]
name = "up"
material = "m"
shape = { type = "rectangle", min = [0.3, 1.0], max = [1.7, 1.6] }
mesh = { size = 0.23 }
[[support]]
on = { body = "low", edge = "bottom" }
fix = ["ux", "uy"]
)";
  if (obstacle)
    s += R"(
[[obstacle]]
name = "drum"
type = "circle"
center = [1.0, 3.0]
radius = 1.45
[[contact]]
slave = { body = "up", edge = "top" }
master = { obstacle = "drum" }
detection = ")" + detection + "\"\n";
  else
    s += R"(
[[contact]]
slave = { body = "up", edge = "bottom" }
master = { body = "low", edge = "top" }
detection = ")" + detection + "\"\n";
  return s;
}

TEST(GapLinearisation, ContactSetRowsMatchFiniteDifferences) {
  for (const std::string element : {"T3", "T6"})
    for (const std::string detection : {"node_to_segment", "mortar"})
      for (bool obstacle : {false, true}) {
        const std::string name = element + " " + detection + (obstacle ? " obstacle" : "");
        const core::Scene scene =
            core::parse_scene(blocks_scene(element, detection, obstacle), "blocks.toml");
        const core::Model model = core::build_model(scene);
        const ContactSet contact(model, parse_contact_scene(scene, "lagrange"), scene);
        // A deformed state: the upper block sheared, rotated a little and pressed in.
        // The lower block bulges a little (its top nodes must not sit under slave nodes).
        const core::Mesh& mesh = model.mesh;
        std::vector<char> upper(mesh.num_nodes(), 0);
        for (size_t el = 0; el < mesh.elements.size(); ++el)
          if (mesh.element_body[el] == 1)
            for (int n : mesh.elements[el])
              if (n >= 0) upper[n] = 1;
        VecX u = VecX::Zero(2 * mesh.num_nodes());
        for (int n = 0; n < mesh.num_nodes(); ++n) {
          const Vec2& p = mesh.nodes[n];
          if (!upper[n]) {
            u[2 * n + 1] = 0.003 * p.y() * std::sin(2.0 * p.x() + 0.4);
            continue;
          }
          u[2 * n] = 0.03 * (p.y() - 1.0) + 0.02 * std::sin(3 * p.x());
          u[2 * n + 1] = -0.01 + 0.015 * (p.x() - 1.0) + 0.004 * std::cos(5 * p.x());
        }
        const RowsAt rows_at = [&](const std::vector<Vec2>& x) {
          VecX v(2 * x.size());
          for (size_t n = 0; n < x.size(); ++n) v.segment<2>(2 * n) = x[n] - model.mesh.nodes[n];
          std::map<int, GapRow> out;
          for (GapRow& r : contact.detect(v, false)) out[r.slot] = std::move(r);
          return out;
        };
        std::vector<Vec2> x(model.mesh.num_nodes());
        for (int n = 0; n < model.mesh.num_nodes(); ++n)
          x[n] = model.mesh.nodes[n] + u.segment<2>(2 * n);
        const TangentError e = check_rows(x, rows_at, 1e-6);
        EXPECT_GT(e.rows, 3) << name;
        // Central differences with h = 1e-6 are good to about 1e-8 here.
        EXPECT_LT(e.gradient, 1e-6) << name;
        EXPECT_LT(e.hessian, 1e-6) << name;
        // Without the curvature (a residual's detection: first-order Jets, mortar included):
        // the same rows, gaps and terms.
        const std::vector<GapRow> full = contact.detect(u, false, true);
        const std::vector<GapRow> first = contact.detect(u, false, false);
        ASSERT_EQ(first.size(), full.size()) << name;
        for (size_t i = 0; i < full.size(); ++i) {
          EXPECT_EQ(first[i].slot, full[i].slot) << name;
          EXPECT_NEAR(first[i].gap, full[i].gap, 1e-13) << name;
          ASSERT_EQ(first[i].terms.size(), full[i].terms.size()) << name;
          for (size_t k = 0; k < full[i].terms.size(); ++k) {
            EXPECT_EQ(first[i].terms[k].first, full[i].terms[k].first) << name;
            EXPECT_LT((first[i].terms[k].second - full[i].terms[k].second).cwiseAbs().maxCoeff(),
                      1e-12) << name;
          }
        }
      }
}

}  // namespace
