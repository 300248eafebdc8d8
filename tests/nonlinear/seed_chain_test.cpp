// The seed's chapter-3 worked examples written as scenes (issue 17): "Ejemplo 02", the chain of
// seven masses on springs with u1 = 0 and u2 − u6 = 0.20 (examples/spring_chain.toml), and
// "Ejemplo 01", two bars in series between supports. Lagrange multipliers reproduce the exact
// displacements and multipliers to round-off; a penalty α reproduces the seed's own penalty
// table (α = 2·10⁶: u1 = 1.4·10⁻⁵, u2..u7 to its five digits) and its error falls as 1/α.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "constraints/contact_scene.hpp"
#include "constraints/contact_set.hpp"
#include "core/model.hpp"
#include "core/probes.hpp"
#include "core/scene.hpp"
#include "nonlinear/load_stepper.hpp"
#include "scene_run.hpp"

using namespace c2d;

namespace {

/// The multiplier of the [[constraint]] named `name` (its one row).
double multiplier(const constraints::ContactReport& report, const std::string& name) {
  for (size_t k = 0; k < report.equality_names.size(); ++k)
    if (report.equality_names[k] == name)
      for (const auto& e : report.equalities)
        if (e.owner == static_cast<int>(k)) return e.multiplier;
  ADD_FAILURE() << "no constraint " << name;
  return 0.0;
}

using Solved = test::SceneRun;

Solved run(const core::Scene& scene, const std::string& method) {
  return test::run_scene(scene, method);
}

core::Scene chain(const std::vector<std::string>& sets = {}) {
  return core::load_scene(std::string(C2D_SOURCE_DIR) + "/examples/spring_chain.toml", sets);
}

/// prefix + text, built without operator+ on a literal (GCC 12 warns falsely, -Wrestrict).
std::string joined(const char* prefix, const std::string& text) {
  std::string out(prefix);
  out.append(text);
  return out;
}

const double kExact[7] = {0, 0.27, 0.275, 0.25, 0.185, 0.07, 0.14};

}  // namespace

TEST(SeedChain, LagrangeGivesTheExactDisplacementsAndMultipliers) {
  for (const std::string method : {"lagrange", "ssn"}) {
    const Solved r = run(chain(), method);
    ASSERT_EQ(r.results.status, SolveStatus::kConverged) << method << ": " << r.results.message;
    for (int i = 0; i < 7; ++i)
      EXPECT_NEAR(r.results.probes.at(joined("u", std::to_string(i + 1))), kExact[i], 1e-10) << method;
    // The seed's λ1 = 28 holds u1 against Σ f = 28; λ2 = 24.5 (its sign is the row's).
    EXPECT_NEAR(std::abs(multiplier(r.report, "support")), 28.0, 1e-10) << method;
    EXPECT_NEAR(std::abs(multiplier(r.report, "u2_minus_u6")), 24.5, 1e-10) << method;
  }
}

TEST(SeedChain, PenaltyReproducesTheSeedsTableAndConvergesAsOneOverAlpha) {
  // The seed's penalty solution with α = 2·10⁶, as printed (five digits).
  const double seed[7] = {1.4e-5, 0.27001, 0.27502, 0.25002, 0.18502, 0.07003, 0.14003};
  double previous = 0.0;
  for (const double alpha : {2e4, 2e5, 2e6}) {
    const std::string k = joined("constraint.penalty.k=", std::to_string(alpha));
    const Solved r = run(chain({k}), "penalty");
    ASSERT_EQ(r.results.status, SolveStatus::kConverged) << r.results.message;
    double error = 0.0;
    for (int i = 0; i < 7; ++i) {
      const double u = r.results.probes.at(joined("u", std::to_string(i + 1)));
      error = std::max(error, std::abs(u - kExact[i]));
      if (alpha == 2e6) {
        EXPECT_NEAR(u, seed[i], 5e-6) << "u" << i + 1;
      }
    }
    // u1 = λ1 / α exactly: the support row's spring carries the 28 N.
    EXPECT_NEAR(r.results.probes.at("u1") * alpha, 28.0, 1e-6 * 28.0);
    if (previous > 0) {
      EXPECT_NEAR(previous / error, 10.0, 0.2) << "α = " << alpha;
    }
    previous = error;
  }
}

// "Ejemplo 01": bars k1 = E1 A1 / L1 = 560,000 and k2 = E2 A2 / L2 = 300,000 N/mm in series,
// F = 200 kN on the middle node, both ends held by `linear` rows: u2 = F / (k1 + k2) = 0.23256
// mm, the end forces 0.13023·10⁶ and 0.06977·10⁶ N.
TEST(SeedChain, TwoBarsBetweenSupports) {
  std::string text = R"(
[analysis]
element = "T3"
[[material]]
name = "block"
E = 1000.0
nu = 0.3
[[support]]
on = { box = [[-1.0, -1.0], [20.0, 2.0]] }
fix = ["uy"]
[[load]]
on = { nearest = [3.0, 0.0] }
force = [200000.0, 0.0]
[[spring]]
between = [ { nearest = [0.0, 0.0] }, { nearest = [3.0, 0.0] } ]
k = 560000.0
[[spring]]
between = [ { nearest = [3.0, 0.0] }, { nearest = [6.0, 0.0] } ]
k = 300000.0
[[probe]]
name = "u2"
quantity = "ux"
at = [3.0, 0.0]
[[constraint]]
name = "left"
type = "linear"
terms = [ { on = { nearest = [0.0, 0.0] }, dof = "ux", coefficient = 1.0 } ]
[[constraint]]
name = "right"
type = "linear"
terms = [ { on = { nearest = [6.0, 0.0] }, dof = "ux", coefficient = 1.0 } ]
)";
  for (int i = 0; i < 3; ++i) {
    // Appended piece by piece (GCC 12 warns falsely, -Wrestrict, on literal + string chains).
    const std::string n = std::to_string(i + 1);
    text.append("[[body]]\nname = \"n").append(n).append("\"\nmaterial = \"block\"\n");
    text.append("shape = { type = \"rectangle\", min = [").append(std::to_string(3.0 * i));
    text.append(", 0.0], max = [").append(std::to_string(3.0 * i + 1.0)).append(", 1.0] }\n");
    text.append("mesh = { size = 1.0 }\n[[constraint]]\nname = \"rigid").append(n);
    text.append("\"\ntype = \"equal\"\non = { body = \"n").append(n).append("\" }\ndof = \"ux\"\n");
  }
  const Solved r = run(core::parse_scene(text, "bars.toml"), "lagrange");
  ASSERT_EQ(r.results.status, SolveStatus::kConverged) << r.results.message;
  EXPECT_NEAR(r.results.probes.at("u2"), 200000.0 / 860000.0, 1e-12);
  EXPECT_NEAR(r.results.probes.at("u2"), 0.23256, 5e-6);
  EXPECT_NEAR(std::abs(multiplier(r.report, "left")), 560000.0 * 200000.0 / 860000.0, 1e-6);
  EXPECT_NEAR(std::abs(multiplier(r.report, "right")), 300000.0 * 200000.0 / 860000.0, 1e-6);
  EXPECT_NEAR(std::abs(multiplier(r.report, "left")), 0.13023e6, 5.0);
}
