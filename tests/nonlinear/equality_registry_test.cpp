// The [[constraint]] registry (issue 14: a constraint type slots in as one class plus one
// registry line): docs/scene.md carries its table, and every registered type passes the shared
// checks on its own example: it parses, its rows have finite coefficients on existing DOFs, a
// rigid translation of the model satisfies them (constraints between parts of a model are
// relative), and a lagrange solve of two stacked blocks under a uniform traction with the
// constraint added converges with the rows satisfied to round-off.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "constraints/contact_scene.hpp"
#include "constraints/contact_set.hpp"
#include "constraints/equality.hpp"
#include "core/model.hpp"
#include "core/scene.hpp"
#include "nonlinear/load_stepper.hpp"

using namespace c2d;
using namespace c2d::constraints;

TEST(EqualityRegistry, DocsCarryTheTable) {
  std::ifstream in(std::string(C2D_SOURCE_DIR) + "/docs/scene.md");
  std::stringstream doc;
  doc << in.rdbuf();
  EXPECT_NE(doc.str().find(equality_table_markdown()), std::string::npos)
      << "docs/scene.md must contain the [[constraint]] table, exactly:\n"
      << equality_table_markdown();
}

class EveryEquality : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryEquality, PassesTheSharedChecks) {
  const EqualityInfo* info = find_equality(GetParam());
  ASSERT_NE(info, nullptr);
  const std::string text = R"(
[analysis]
kind = "plane_stress"
[[material]]
name = "m"
E = 1000.0
nu = 0.3
[[body]]
name = "low"
material = "m"
shape = { type = "rectangle", min = [0.0, 0.0], max = [2.0, 1.0] }
mesh = { size = 0.3 }
[[body]]
name = "up"
material = "m"
shape = { type = "rectangle", min = [0.0, 1.0], max = [2.0, 1.5] }
mesh = { size = 0.2 }
[[support]]
on = { body = "low", edge = "bottom" }
fix = ["uy"]
[[support]]
on = { nearest = [0.0, 0.0] }
fix = ["ux"]
[[load]]
on = { body = "up", edge = "top" }
traction = [0.0, -10.0]
# The blocks touch but are not joined: the tie holds them together, the other types need
# the tie too (added below for them), so every example is a solvable model.
[[constraint]]
name = "under_test"
type = ")" + info->name + "\"\n" + info->example + "\n" +
                           (info->name == "tie" ? "" : R"(
[[constraint]]
name = "glue"
type = "tie"
slave = { body = "up", edge = "bottom" }
master = { body = "low", edge = "top" }
)");
  const core::Scene scene = core::parse_scene(text, "example.toml");
  const core::Model model = core::build_model(scene);
  const ContactSet set(model, parse_contact_scene(scene, "lagrange"), scene);
  int own = 0;
  for (const EqualityRow& row : set.equalities().constraint_rows()) {
    if (row.owner != 0) continue;
    ++own;
    double translated = 0.0, size = 0.0;
    for (const auto& [dof, a] : row.terms) {
      ASSERT_GE(dof, 0);
      ASSERT_LT(dof, model.mesh.num_dofs());
      ASSERT_TRUE(std::isfinite(a));
      translated += a * (dof % 2 == 0 ? 0.3 : -0.7);  // u = (0.3, −0.7) everywhere
      size += std::abs(a);
    }
    EXPECT_NEAR(translated, row.rhs, 1e-12 * size) << info->name;
  }
  EXPECT_GT(own, 0) << info->name;
  constraints::ContactReport report;
  const core::Results r = nonlinear::solve_linear_static(model, scene.analysis, &set, &report);
  ASSERT_EQ(r.status, SolveStatus::kConverged) << info->name << ": " << r.message;
  EXPECT_LT(report.max_equality_violation, 1e-12) << info->name;
  for (const auto& e : report.equalities) EXPECT_TRUE(std::isfinite(e.multiplier));
}

INSTANTIATE_TEST_SUITE_P(Types, EveryEquality, ::testing::ValuesIn(equality_names()));
