// The friction-law registry (issue 14: a friction law slots in as one class plus one registry
// line): docs/scene.md carries its table, a table without `law` names the law whose keys it
// gives, and every registered law passes the shared checks on its own example: a 2 × 0.25 block
// pressed on a rigid floor by p (N = 2p over the width W = 2) and driven sideways slides with a
// tangential reaction of exactly the law's bound, offset(W) + slope N, with the exact methods
// (to 1e-8 of N) and every other method (to 1e-6 of N). The pressures are 0.5 and 20: the
// examples' parameters put every slave row on one piece of its law at each, and a law with two
// pieces meets both. (The friction F at the base and the drive at the top make a couple F h
// that spreads the base pressure linearly over p ± 0.375 F / W·2, so the block stays in full
// contact while F < 1.33 N: within the examples' bounds at both pressures.)
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "constraints/contact_scene.hpp"
#include "constraints/friction_law.hpp"
#include "core/errors.hpp"
#include "core/scene.hpp"
#include "scene_run.hpp"

using namespace c2d;
using namespace c2d::constraints;

namespace {

std::string sliding_block(double pressure, const std::string& friction) {
  std::string s = R"([analysis]
kind = "plane_strain"
element = "T3"
[[material]]
name = "m"
E = 1000.0
nu = 0.3
[[body]]
name = "block"
material = "m"
shape = { type = "rectangle", min = [0.0, 0.0], max = [2.0, 0.25] }
mesh = { size = 0.125 }
[[obstacle]]
name = "floor"
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[[support]]
on = { body = "block", edge = "top" }
ux = 0.05
[[load]]
on = { body = "block", edge = "top" }
traction = [0.0, )";
  s.append(std::to_string(-pressure)).append(R"(]
[[probe]]
name = "rx"
on = { body = "block", edge = "top" }
quantity = "reaction_x"
reduce = "sum"
[[contact]]
name = "base"
slave = { body = "block", edge = "bottom" }
master = { obstacle = "floor" }
[contact.friction]
)");
  return s.append(friction).append("\n");
}

core::Scene parse(const std::string& text) { return core::parse_scene(text, "block.toml"); }

}  // namespace

TEST(FrictionLawRegistry, DocsCarryTheTable) {
  std::ifstream in(std::string(C2D_SOURCE_DIR) + "/docs/scene.md");
  std::stringstream doc;
  doc << in.rdbuf();
  EXPECT_NE(doc.str().find(friction_law_table_markdown()), std::string::npos)
      << "docs/scene.md must contain the friction-law table, exactly:\n"
      << friction_law_table_markdown();
}

// Without `law`, the keys name the law; with it, they must be that law's; a coefficient of 0 is
// frictionless; keys of no law are refused naming the laws' keys.
TEST(FrictionLawRegistry, KeysNameTheLaw) {
  for (const FrictionLawInfo& law : friction_law_registry()) {
    SCOPED_TRACE(law.name);
    const core::Scene scene = parse(sliding_block(1.0, law.example));
    EXPECT_EQ(parse_contact_scene(scene).pairs.at(0).friction.law, law.name);
    const core::Scene named = parse(sliding_block(1.0, "law = \"" + law.name + "\"\n" + law.example));
    EXPECT_EQ(parse_contact_scene(named).pairs.at(0).friction.law, law.name);
  }
  EXPECT_FALSE(parse_contact_scene(parse(sliding_block(1.0, "coefficient = 0.0")))
                   .pairs.at(0).friction.enabled());
  try {
    parse_contact_scene(parse(sliding_block(1.0, "penalty_ratio = 2.0")));
    FAIL() << "a friction table with no law's keys was accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("block.toml:"), std::string::npos) << m;
    EXPECT_NE(m.find("contact[0].friction"), std::string::npos) << m;
    for (const FrictionLawInfo& law : friction_law_registry())
      EXPECT_NE(m.find("(" + law.name + ")"), std::string::npos) << m;
  }
  EXPECT_THROW(parse_contact_scene(parse(sliding_block(1.0, "law = \"tresca\"\ncoefficient = 0.3"))),
               InputError);
}

class EveryFrictionLaw : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryFrictionLaw, SlidingBlockCarriesTheLawsBound) {
  const FrictionLawInfo* info = find_friction_law(GetParam());
  ASSERT_NE(info, nullptr);
  for (const double p : {0.5, 20.0}) {
    const core::Scene scene = parse(sliding_block(p, info->example));
    const ContactSceneSpec spec = parse_contact_scene(scene);
    const FrictionLaw& law = *spec.pairs.at(0).friction.model;
    const double n = 2 * p, expected = law.bound(n, 2.0).at(n);
    for (const std::string m : {"lagrange", "ssn", "ipopt", "auglag", "penalty", "adaptive_penalty"}) {
      SCOPED_TRACE("p = " + std::to_string(p) + ", " + m);
      const test::SceneRun r = test::run_scene(scene, m);
      ASSERT_EQ(r.results.status, SolveStatus::kConverged) << r.results.message;
      const double tol = (m == "lagrange" || m == "ssn") ? 1e-8 : 1e-6;
      EXPECT_NEAR(r.report.total_force, n, tol * n);
      EXPECT_NEAR(r.results.probes.at("rx"), expected, tol * n);
      EXPECT_EQ(r.report.stick_nodes, 0);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Registry, EveryFrictionLaw, ::testing::ValuesIn(friction_law_names()),
                         [](const auto& info) { return info.param; });
