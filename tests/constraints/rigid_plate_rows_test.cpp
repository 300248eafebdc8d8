// A rigid plate's rows against finite differences and against the rigid motion they describe:
// in load-stepped runs every row carries its exact gradient (terms) and second derivatives
// (curvature), and an exact rigid motion of plate and edge satisfies every row whatever the angle.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "constraints/contact_scene.hpp"
#include "constraints/equality_constraints.hpp"
#include "core/model.hpp"
#include "core/scene.hpp"

using namespace c2d;
using namespace c2d::constraints;

namespace {

/// A block [0,2]×[0,1] with a plate on its top edge (free: reference at its middle).
std::string block_scene(const std::string& attach) {
  return R"(
[analysis]
element = "T6"
[[material]]
name = "m"
E = 1000.0
nu = 0.3
[[body]]
name = "b"
material = "m"
shape = { type = "rectangle", min = [0.0, 0.0], max = [2.0, 1.0] }
mesh = { size = 0.5 }
[[support]]
on = { body = "b", edge = "bottom" }
fix = ["ux", "uy"]
[[plate]]
on = { body = "b", edge = "top" }
reference = [1.0, 1.2]
attach = ")" + attach + R"("
)" + (attach == "normal" ? "fix = [\"ux\"]\n" : "");
}

struct Fixture {
  core::Scene scene;
  core::Model model;
  ContactSceneSpec spec;
  std::unique_ptr<EqualityConstraints> equalities;
  explicit Fixture(const std::string& attach)
      : scene(core::parse_scene(block_scene(attach), "plate.toml")),
        model(core::build_model(scene)),
        spec(parse_contact_scene(scene, "")),
        equalities(std::make_unique<EqualityConstraints>(model, spec.equalities)) {}
};

/// A displacement that moves every node and turns the plate by `theta`.
VecX some_state(const core::Model& model, double theta) {
  VecX u(model.dofs.num_dofs());
  for (int i = 0; i < u.size(); ++i) u[i] = 0.01 * std::sin(1.3 * i + 0.4);
  const int q = model.plates[0].dof;
  u[q] = 0.03, u[q + 1] = -0.02, u[q + 2] = theta;
  return u;
}

/// The largest relative error of the terms against central differences of the values, and of
/// the curvature against central differences of the terms (full DOF indices).
std::pair<double, double> tangent_error(const EqualityConstraints& equalities, const VecX& u,
                                        double h) {
  const std::vector<EqualityRow> rows = equalities.rows_at(u, false);
  double gerr = 0.0, herr = 0.0, gmax = 1e-300, hmax = 1e-300;
  for (size_t j = 0; j < rows.size(); ++j) {
    std::map<int, double> grad;
    for (const auto& [dof, a] : rows[j].terms) grad[dof] += a, gmax = std::max(gmax, std::abs(a));
    std::map<std::pair<int, int>, double> hess;
    for (const auto& [a, b, v] : rows[j].curvature) hess[{a, b}] += v, hmax = std::max(hmax, std::abs(v));
    for (const auto& [dof, a] : grad) {
      VecX up = u, um = u;
      up[dof] += h, um[dof] -= h;
      const auto rp = equalities.rows_at(up, false), rm = equalities.rows_at(um, false);
      const double fd = (equalities.values(rp, up)[j] - equalities.values(rm, um)[j]) / (2 * h);
      gerr = std::max(gerr, std::abs(fd - a));
      // d(terms)/du_dof against the curvature's column dof.
      std::map<int, double> tp, tm;
      for (const auto& [d, v] : rp[j].terms) tp[d] += v;
      for (const auto& [d, v] : rm[j].terms) tm[d] += v;
      for (const auto& [d, v] : tp) {
        const double fd2 = (v - tm[d]) / (2 * h);
        const auto it = hess.find({d, dof});
        herr = std::max(herr, std::abs(fd2 - (it == hess.end() ? 0.0 : it->second)));
      }
    }
  }
  return {gerr / gmax, herr / hmax};
}

}  // namespace

TEST(RigidPlateRows, TangentMatchesCentralDifferences) {
  for (const std::string attach : {"all", "normal"}) {
    Fixture f(attach);
    for (double theta : {0.0, 0.4, 1.3}) {
      const auto [g, h] = tangent_error(*f.equalities, some_state(f.model, theta), 1e-6);
      EXPECT_LT(g, 1e-8) << attach << " θ = " << theta;
      EXPECT_LT(h, 1e-6) << attach << " θ = " << theta;
    }
  }
}

// An exact rigid motion of the plate with its edge, at any angle, satisfies the exact rows to
// round-off (the edge follows the rotation, not its linearisation); the linear rows do not.
TEST(RigidPlateRows, ExactRigidMotionSatisfiesTheRows) {
  for (const std::string attach : {"all", "normal"}) {
    Fixture f(attach);
    const core::RigidPlate& plate = f.model.plates[0];
    const Vec2 t(0.3, -0.1);
    for (double theta : {0.2, 1.0, 2.5}) {
      VecX u = VecX::Zero(f.model.dofs.num_dofs());
      Eigen::Matrix2d rot;
      rot << std::cos(theta), -std::sin(theta), std::sin(theta), std::cos(theta);
      for (int n = 0; n < f.model.mesh.num_nodes(); ++n) {
        const Vec2 x = f.model.mesh.nodes[n];
        u.segment<2>(2 * n) = plate.reference + t + rot * (x - plate.reference) - x;
      }
      u.segment<2>(plate.dof) = t;
      u[plate.dof + 2] = theta;
      const VecX c = f.equalities->values(f.equalities->rows_at(u, false), u);
      EXPECT_LT(c.cwiseAbs().maxCoeff(), 1e-13) << attach << " θ = " << theta;
      const VecX lin = f.equalities->values(f.equalities->rows_at(u, true), u);
      EXPECT_GT(lin.cwiseAbs().maxCoeff(), 1e-3) << attach << " θ = " << theta;
    }
  }
}
