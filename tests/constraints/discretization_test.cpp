// Shared checks over every registered contact discretization: on two stacked blocks with
// matching meshes 0.1 apart (top block slave, bottom block master), every slave node gets a row
// whose gap is the analytic 0.1, with the upward normal and a slot of its own; a rigid
// downward translation d of the top block lowers every gap by exactly d (to 1e-12); a
// discretization that takes obstacles does the same against a rigid floor.
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>

#include "constraints/contact_scene.hpp"
#include "constraints/contact_pairs.hpp"
#include "constraints/discretization.hpp"
#include "core/errors.hpp"
#include "core/model.hpp"
#include "core/scene.hpp"

using namespace c2d;
using namespace c2d::constraints;

namespace {

std::string stacked_blocks(const std::string& detection, bool floor) {
  std::string s =
      "[analysis]\nelement = \"T3\"\n"
      "[[material]]\nname = \"m\"\nE = 1000.0\nnu = 0.3\n"
      "[[body]]\nname = \"top\"\nmaterial = \"m\"\n"
      "shape = { type = \"rectangle\", min = [0.0, 1.1], max = [2.0, 2.1] }\nmesh = { size = 0.25 }\n";
  if (floor)
    return s + "[[obstacle]]\nname = \"floor\"\ntype = \"line\"\npoint = [0.0, 1.0]\nnormal = [0.0, 1.0]\n"
               "[[contact]]\nslave = { body = \"top\", edge = \"bottom\" }\nmaster = { obstacle = \"floor\" }\n"
               "detection = \"" + detection + "\"\n";
  return s +
         "[[body]]\nname = \"base\"\nmaterial = \"m\"\n"
         "shape = { type = \"rectangle\", min = [0.0, 0.0], max = [2.0, 1.0] }\nmesh = { size = 0.25 }\n"
         "[[contact]]\nslave = { body = \"top\", edge = \"bottom\" }\nmaster = { body = \"base\", edge = \"top\" }\n"
         "detection = \"" + detection + "\"\n";
}

void expect_gaps(const ContactPairs& pairs, const core::Model& model, double drop) {
  VecX u = VecX::Zero(model.mesh.num_dofs());
  for (int n = 0; n < model.mesh.num_nodes(); ++n)
    if (model.mesh.nodes[n].y() > 1.05) u[2 * n + 1] = -drop;
  const std::vector<GapRow> rows = pairs.detect(u);
  ASSERT_EQ(static_cast<int>(rows.size()), pairs.num_slave_nodes());
  std::set<int> slots;
  for (const GapRow& r : rows) {
    EXPECT_NEAR(r.gap, 0.1 - drop, 1e-12) << "slave node " << r.slave;
    EXPECT_NEAR(r.normal.y(), 1.0, 1e-12);
    EXPECT_TRUE(r.slot >= 0 && r.slot < pairs.num_slots());
    EXPECT_TRUE(slots.insert(r.slot).second) << "slot " << r.slot << " twice";
  }
}

class EveryDiscretization : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(EveryDiscretization, StackedBlocksGapsAreExactAndFollowARigidTranslation) {
  const core::Scene scene = core::parse_scene(stacked_blocks(GetParam(), false), "blocks.toml");
  const core::Model model = core::build_model(scene);
  const ContactPairs pairs(model, parse_contact_scene(scene), scene);
  EXPECT_EQ(pairs.num_slave_nodes(), 9);  // 2.0 / 0.25 + 1 nodes on the bottom edge
  expect_gaps(pairs, model, 0.0);
  expect_gaps(pairs, model, 0.03);
}

TEST_P(EveryDiscretization, AgainstARigidFloorWhenItTakesObstacles) {
  const DiscretizationInfo* info = find_discretization(GetParam());
  ASSERT_NE(info, nullptr);
  if (!info->obstacles) {
    EXPECT_THROW(parse_contact_scene(core::parse_scene(stacked_blocks(GetParam(), true), "f.toml")),
                 InputError);
    return;
  }
  const core::Scene scene = core::parse_scene(stacked_blocks(GetParam(), true), "floor.toml");
  const core::Model model = core::build_model(scene);
  const ContactPairs pairs(model, parse_contact_scene(scene), scene);
  expect_gaps(pairs, model, 0.0);
  expect_gaps(pairs, model, 0.03);
}

INSTANTIATE_TEST_SUITE_P(Contact, EveryDiscretization, ::testing::ValuesIn(discretization_names()));

TEST(DiscretizationRegistry, DocsSceneMdHoldsTheRegistrysDetectionTable) {
  std::ifstream in(std::string(C2D_SOURCE_DIR) + "/docs/scene.md");
  std::stringstream doc;
  doc << in.rdbuf();
  EXPECT_NE(doc.str().find(discretization_table_markdown()), std::string::npos)
      << "docs/scene.md must contain the detection table, exactly:\n" << discretization_table_markdown();
}
