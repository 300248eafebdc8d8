// Coulomb and Tresca friction (issue 18) against closed forms, with every method:
//  - a block driven over a rigid floor slides with a tangential reaction of exactly μ N, and
//    under a tangential load it sticks below μ N and cannot be held above (a named status);
//  - a Tresca bound caps the shear traction at the bound;
//  - the frictional patch test: stacked blocks, non-matching meshes, mortar, uniform pressure
//    and shear cross the interface exactly with the exact methods;
//  - Cattaneo–Mindlin (examples/cattaneo_mindlin.toml): the stick zone c = b √(1 − Q/μP) and
//    the shear profile; loading normal and tangential together sticks everywhere instead
//    (Mindlin–Deresiewicz), and unloading the tangential force reverses slip over
//    c'' < |x| < b with c'' = b √(1 − Q/2μP), leaving locked-in shear.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/scene.hpp"
#include "scene_run.hpp"

using namespace c2d;

namespace {

const std::vector<std::string> kMethods = {"lagrange", "ssn",    "ipopt",
                                           "auglag",   "penalty", "adaptive_penalty"};

// A 2 × 1 block (E = 1000, ν = 0.3, plane strain) on a rigid floor, pressed by p = 1 on its top
// (N = 2), with Coulomb μ = 0.3; `top` adds the top edge's tangential drive.
std::string block(const std::string& top, const std::string& friction = "{ coefficient = 0.3 }",
                  double shear = 0.0, double pressure = 1.0) {
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
shape = { type = "rectangle", min = [0.0, 0.0], max = [2.0, 1.0] }
mesh = { size = 0.25 }
[[obstacle]]
name = "floor"
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[[load]]
on = { body = "block", edge = "top" }
traction = [)";
  s.append(std::to_string(shear)).append(", ").append(std::to_string(-pressure)).append(R"(]
[[contact]]
name = "base"
slave = { body = "block", edge = "bottom" }
master = { obstacle = "floor" }
friction = )");
  s.append(friction).append("\n").append(top).append(R"(
[[probe]]
name = "rx"
on = { body = "block", edge = "top" }
quantity = "reaction_x"
reduce = "sum"
)");
  return s;
}

const std::string kDriven = "[[support]]\non = { body = \"block\", edge = \"top\" }\nux = 0.01\n";

double probe(const test::SceneRun& r, const std::string& name) {
  const auto it = r.results.probes.find(name);
  return it == r.results.probes.end() ? std::nan("") : it->second;
}

}  // namespace

// Driven 0.01 sideways (a hundred times the stick limit), every slave node slips and the
// reaction is μ N: 0.6 to 1e-8 (all methods reach 1e-11 or better).
TEST(Friction, BlockDrivenOverAFloorSlidesWithReactionMuN) {
  for (const std::string& m : kMethods) {
    SCOPED_TRACE(m);
    const test::SceneRun r = test::run_scene(core::parse_scene(block(kDriven), "block.toml"), m);
    ASSERT_EQ(r.results.status, SolveStatus::kConverged) << r.results.message;
    EXPECT_NEAR(r.report.total_force, 2.0, 1e-8);
    EXPECT_NEAR(probe(r, "rx") / r.report.total_force, 0.3, 1e-8);
    EXPECT_NEAR(r.report.tangent_force, -0.6, 1e-8);  // on the slave along +x
    EXPECT_EQ(r.report.stick_nodes, 0);
    EXPECT_GT(r.report.slip_nodes, 0);
  }
}

// Under a tangential traction q on the top: q = 0.2 < μ p holds (the friction carries q W =
// 0.4 exactly, equilibrium); q = 0.4 > μ p cannot be held, and every method says so with a
// named status instead of an answer.
TEST(Friction, BlockUnderATangentialLoadSticksBelowMuNAndIsRefusedAbove) {
  for (const std::string& m : kMethods) {
    SCOPED_TRACE(m);
    const test::SceneRun held =
        test::run_scene(core::parse_scene(block("", "{ coefficient = 0.3 }", 0.2), "b.toml"), m);
    ASSERT_EQ(held.results.status, SolveStatus::kConverged) << held.results.message;
    EXPECT_NEAR(held.report.tangent_force, -0.4, 1e-8);
    EXPECT_GT(held.report.stick_nodes, 0);
    const test::SceneRun slides =
        test::run_scene(core::parse_scene(block("", "{ coefficient = 0.3 }", 0.4), "b.toml"), m);
    EXPECT_NE(slides.results.status, SolveStatus::kConverged);
    EXPECT_FALSE(slides.results.message.empty());
    EXPECT_TRUE(std::isfinite(slides.report.tangent_force));
  }
}

// Coulomb with a shear limit, μ = 0.3 and τ = 0.5: at p = 0.5 the block slides with μN = 0.3 (the
// base pressure stays below τ/μ everywhere); at p = 20 with τW = 1.0 (above it everywhere).
TEST(Friction, CoulombLimitedSlidesWithTheSmallerOfMuNAndTheShearLimit) {
  for (const std::string& m : kMethods) {
    SCOPED_TRACE(m);
    const std::string law = "{ coefficient = 0.3, bound = 0.5 }";
    const test::SceneRun low =
        test::run_scene(core::parse_scene(block(kDriven, law, 0.0, 0.5), "l.toml"), m);
    ASSERT_EQ(low.results.status, SolveStatus::kConverged) << low.results.message;
    EXPECT_NEAR(probe(low, "rx"), 0.3, 1e-8);
    const test::SceneRun high =
        test::run_scene(core::parse_scene(block(kDriven, law, 0.0, 20.0), "h.toml"), m);
    ASSERT_EQ(high.results.status, SolveStatus::kConverged) << high.results.message;
    EXPECT_NEAR(probe(high, "rx"), 1.0, 1e-8);
  }
}

// Tresca with a bound of 0.2 on the shear traction: the driven block carries 0.2 × 2 = 0.4.
TEST(Friction, TrescaBoundCapsTheShearTraction) {
  for (const std::string& m : kMethods) {
    SCOPED_TRACE(m);
    const test::SceneRun r =
        test::run_scene(core::parse_scene(block(kDriven, "{ bound = 0.2 }"), "t.toml"), m);
    ASSERT_EQ(r.results.status, SolveStatus::kConverged) << r.results.message;
    EXPECT_NEAR(probe(r, "rx"), 0.4, 1e-8);
  }
}

namespace {

// Two blocks of different stiffness (ν = 0, so a uniform state is compatible across a sticking
// interface), meshed independently, in the uniform state σ_yy = −10, σ_xy = 2: the tractions of
// that state on every outer edge, u_y = 0 on the bottom and u_x = 0 at one corner. q/p = 0.2 <
// μ = 0.3: the interface sticks and carries p = 10 and shear 2 uniformly.
std::string frictional_patch(const std::string& element) {
  std::string s = "[analysis]\nkind = \"plane_strain\"\nelement = \"";
  s.append(element).append(R"("
[[material]]
name = "soft"
E = 1000.0
nu = 0.0
[[material]]
name = "stiff"
E = 3000.0
nu = 0.0
[[body]]
name = "low"
material = "stiff"
shape = { type = "rectangle", min = [0.0, 0.0], max = [2.0, 1.0] }
mesh = { size = 0.23 }
[[body]]
name = "up"
material = "soft"
shape = { type = "rectangle", min = [0.0, 1.0], max = [2.0, 2.0] }
mesh = { size = 0.17 }
[[support]]
on = { body = "low", edge = "bottom" }
fix = ["uy"]
[[support]]
on = { nearest = [0.0, 0.0] }
fix = ["ux"]
[[load]]
on = { body = "up", edge = "top" }
traction = [2.0, -10.0]
[[load]]
on = { body = "up", edge = "left" }
traction = [0.0, -2.0]
[[load]]
on = { body = "up", edge = "right" }
traction = [0.0, 2.0]
[[load]]
on = { body = "low", edge = "left" }
traction = [0.0, -2.0]
[[load]]
on = { body = "low", edge = "right" }
traction = [0.0, 2.0]
[[load]]
on = { body = "low", edge = "bottom" }
traction = [-2.0, 0.0]
[[contact]]
name = "interface"
slave = { body = "up", edge = "bottom" }
master = { body = "low", edge = "top" }
detection = "mortar"
friction = { coefficient = 0.3 }
)");
  return s;
}

}  // namespace

TEST(Friction, PatchTestTransmitsUniformPressureAndShearExactly) {
  for (const std::string element : {"T3", "T6"})
    for (const std::string m : {"lagrange", "ssn", "ipopt", "auglag"}) {
      SCOPED_TRACE(element + " " + m);
      const test::SceneRun r =
          test::run_scene(core::parse_scene(frictional_patch(element), "patch.toml"), m);
      ASSERT_EQ(r.results.status, SolveStatus::kConverged) << r.results.message;
      ASSERT_GT(r.report.nodes.size(), 10u);
      for (const auto& n : r.report.nodes) {
        EXPECT_NEAR(n.pressure, 10.0, 1e-7) << "node " << n.node;  // 1e-8 relative
        EXPECT_NEAR(n.shear, -2.0, 2e-8) << "node " << n.node;     // on the slave along +x
        EXPECT_EQ(n.state, constraints::FrictionState::kStick);
      }
    }
}

namespace {

// The example's reference: b = 2.3489 mm, p0 = 271.03 MPa, μ = 0.3, P = 1000, Q = 150 N/mm.
constexpr double kB = 2.3489, kMu = 0.3, kP = 1000.0, kQ = 150.0;

core::Scene cattaneo(const std::vector<std::string>& sets) {
  return core::load_scene(std::string(C2D_SOURCE_DIR) + "/examples/cattaneo_mindlin.toml", sets);
}

double shear_profile_error(const core::Scene& scene, const test::SceneRun& r);

/// The half-width of the sticking zone, from the stick nodes' extreme positions.
double stick_half_width(const constraints::ContactReport& report) {
  double lo = 1e300, hi = -1e300;
  for (const auto& n : report.nodes)
    if (n.state == constraints::FrictionState::kStick) lo = std::min(lo, n.x.x()), hi = std::max(hi, n.x.x());
  return 0.5 * (hi - lo);
}

}  // namespace

// The example with ssn, lagrange and auglag: stick half-width c = b √(1 − Q/μP) = 1.6609 mm
// within 2 % + one node spacing (0.06 mm); the stick zone's measured length within 2 %; the
// shear profile's L2 error over |x| < 1.5 b below 3 % (1.9 to 2.3 % measured). The contact
// forces' resultant on the cylinder is the cap's load (−Q, P) to 1e-6 P (Newton's test is
// 1e-8 of the load), and the reported tangential force, its component along the surface's
// reference tangent, is Q to 1e-4 (finite strain moves the pressure's centre by 2.5e-3 mm
// under Q, and with it the tilt of the mean normal: 3.3e-5 measured; the sum of the nodes'
// forces along their own deformed tangents, reported before, read 5.5e-4 off).
TEST(Friction, CattaneoMindlinStickZoneAndShearProfile) {
  const double c = kB * std::sqrt(1.0 - kQ / (kMu * kP));
  for (const std::string m : {"lagrange", "ssn", "auglag"}) {
    SCOPED_TRACE(m);
    const core::Scene scene = cattaneo({});
    const test::SceneRun r = test::run_scene(scene, m);
    ASSERT_EQ(r.results.status, SolveStatus::kConverged) << r.results.message;
    EXPECT_NEAR(stick_half_width(r.report), c, 0.02 * c + 0.06);
    EXPECT_NEAR(r.report.stick_length / (2 * c), 1.0, 0.02);
    EXPECT_NEAR(r.report.length / (2 * kB), 1.0, 0.01);
    EXPECT_LT(shear_profile_error(scene, r), 0.03);
    EXPECT_GT(r.report.slip_nodes, 0);
    EXPECT_NEAR(r.report.resultant.x(), -kQ, 1e-6 * kP);
    EXPECT_NEAR(r.report.resultant.y(), kP, 1e-6 * kP);
    EXPECT_NEAR(r.report.tangent_force / -kQ, 1.0, 1e-4);
  }
}

// Path dependence: P and Q applied together (both amplitudes equal to the load factor, Q/P <
// μ) stick everywhere, where P then Q slips over c < |x| < b (Mindlin and Deresiewicz; equal
// bodies, so nothing couples the normal and tangential problems). Then, loaded P, Q and Q
// unloaded to 0: the reverse slip zone reaches in to c'' = b √(1 − Q/2μP) = 2.0342 mm, the
// tangential force returns to 0 and shear stays locked in.
TEST(Friction, CattaneoMindlinPathDependence) {
  const std::vector<std::string> coarse = {"body[0].mesh.refine[0].size=0.08",
                                           "body[1].mesh.refine[0].size=0.08"};
  std::vector<std::string> together = coarse;
  together.push_back("load[0].amplitude=[[0.0,0.0],[1.0,1.0]]");
  together.push_back("load[1].amplitude=[[0.0,0.0],[1.0,1.0]]");
  together.push_back("analysis.steps=4");
  const core::Scene both = cattaneo(together);
  const test::SceneRun r = test::run_scene(both, "lagrange");
  ASSERT_EQ(r.results.status, SolveStatus::kConverged) << r.results.message;
  // At most the two outermost nodes at each edge of the contact, where the pressure vanishes
  // (the 4-step run: 8 before newly closing rows measured their slip from first contact).
  EXPECT_LE(r.report.slip_nodes, 4);
  EXPECT_NEAR(r.report.stick_length / r.report.length, 1.0, 0.05);

  std::vector<std::string> unload = coarse;
  unload.push_back("load[0].amplitude=[[0.0,0.0],[0.3333,1.0],[1.0,1.0]]");
  unload.push_back("load[1].amplitude=[[0.0,0.0],[0.3333,0.0],[0.6667,1.0],[1.0,0.0]]");
  unload.push_back("analysis.steps=12");
  const test::SceneRun u = test::run_scene(cattaneo(unload), "lagrange");
  ASSERT_EQ(u.results.status, SolveStatus::kConverged) << u.results.message;
  const double c2 = kB * std::sqrt(1.0 - kQ / (2 * kMu * kP));
  EXPECT_NEAR(stick_half_width(u.report), c2, 0.02 * c2 + 0.08);
  EXPECT_LT(std::abs(u.report.tangent_force), 1e-3 * kQ);
  double locked = 0.0, slipped = 0.0;
  for (const auto& n : u.report.nodes) {
    locked = std::max(locked, std::abs(n.shear));
    slipped = std::max(slipped, n.accumulated_slip);
  }
  EXPECT_GT(locked, 0.05 * kMu * 271.03);  // shear locked in at zero tangential force
  EXPECT_GT(slipped, 0.0);
}

// The shear traction node by node (issue 34 item 4), mortar, with finite and with small strain,
// ssn, lagrange and auglag: at every slave node inside 0.9 c within 2 % of μ p0 of the
// Cattaneo–Mindlin profile (measured, worst node: 1.08 % finite, 0.76 % small strain; the same
// for the three methods). Inside c the profile's √ kink at c, where the measured zone ends 0.3 %
// short, takes the nearest nodes to 3.6 % (finite) and 4.7 % (small). With small strain the
// contact forces' tangential resultant is −Q to 1e-9 Q (7e-11 to 2e-10 measured), the
// analysis being linear: nothing else to balance. node_to_segment on these non-matching T6
// meshes leaves 1.9–2.2 % at this mesh and 7.8 % with the block shifted by half a node spacing
// (collocation at non-matching nodes; mortar's figure does not move), so it is not asserted.
TEST(Friction, CattaneoMindlinMortarShearAtEveryNode) {
  const double c = kB * std::sqrt(1.0 - kQ / (kMu * kP)), p0 = 2.0 * kP / (std::numbers::pi * kB);
  for (const bool small : {false, true})
    for (const std::string m : {"lagrange", "ssn", "auglag"}) {
      SCOPED_TRACE(m + (small ? " small strain" : " finite strain"));
      std::vector<std::string> sets = {"contact[0].detection=\"mortar\""};
      if (small) sets.push_back("analysis.geometric_nonlinearity=false");
      const test::SceneRun r = test::run_scene(cattaneo(sets), m);
      ASSERT_EQ(r.results.status, SolveStatus::kConverged) << r.results.message;
      const double sign = r.report.tangent_force < 0 ? -1.0 : 1.0;
      double worst = 0.0;
      int nodes = 0;
      for (const auto& n : r.report.nodes) {
        const double x = n.x.x();
        if (std::abs(x) >= 0.9 * c) continue;
        const double q =
            kMu * p0 *
            (std::sqrt(1 - x * x / (kB * kB)) - (c / kB) * std::sqrt(1 - x * x / (c * c)));
        worst = std::max(worst, std::abs(sign * n.shear - q) / (kMu * p0));
        ++nodes;
      }
      EXPECT_GT(nodes, 80);
      EXPECT_LT(worst, 0.02);
      if (small)
        EXPECT_NEAR(r.report.resultant.x(), -kQ, 1e-9 * kQ);
      else
        EXPECT_NEAR(r.report.resultant.x(), -kQ, 1e-6 * kP);
    }
}

namespace {

/// The summary's measure (app/report/hertz.cpp, not linked into the nonlinear tests): the L2
/// error over |x| < 1.5 b against the Cattaneo–Mindlin profile, midpoint rule on the nodes.
double shear_profile_error(const core::Scene& scene, const test::SceneRun& r) {
  const double p0 = scene.reference.at("p_max"), b = scene.reference.at("contact_length") / 2,
               c = scene.reference.at("stick_length") / 2, mu = scene.reference.at("coefficient");
  const double sign = r.report.tangent_force < 0 ? -1.0 : 1.0;
  double err2 = 0.0, ref2 = 0.0;
  std::vector<std::pair<double, double>> pts;
  for (const auto& n : r.report.nodes) pts.emplace_back(n.x.x(), sign * n.shear);
  std::sort(pts.begin(), pts.end());
  for (size_t i = 0; i + 1 < pts.size(); ++i) {
    const double x = 0.5 * (pts[i].first + pts[i + 1].first), w = pts[i + 1].first - pts[i].first;
    if (std::abs(x) > 1.5 * b) continue;
    const double q = 0.5 * (pts[i].second + pts[i + 1].second);
    double qa = std::abs(x) < b ? mu * p0 * std::sqrt(1 - x * x / (b * b)) : 0.0;
    if (std::abs(x) < c) qa -= mu * p0 * (c / b) * std::sqrt(1 - x * x / (c * c));
    err2 += w * (q - qa) * (q - qa);
    ref2 += w * qa * qa;
  }
  return std::sqrt(err2 / ref2);
}

}  // namespace

namespace {

// GetFEM's Cattaneo–Mindlin problem (shared/peers/cattaneo_rigid.toml): a steel half cylinder
// (R = 10) on a rigid flat with Coulomb friction (μ = 0.3) from first touch, P = 1000, then
// Q = 150. The rigid flat couples the normal and tangential problems (Spence), so there is no
// closed form; GetFEM 5.4 (integral multipliers, T6) gives c/b_Hertz = 0.4352, 0.4273, 0.4332
// at contact-surface sizes b/20, b/40, b/80 (this repository's peer script, 2026-11-26).
std::string rigid_flat_cattaneo(double size) {
  return R"(
[analysis]
kind = "plane_strain"
element = "T6"
geometric_nonlinearity = true
steps = 6
[[material]]
name = "steel"
E = 210000.0
nu = 0.3
[[body]]
name = "cylinder"
material = "steel"
shape = { type = "disk_segment", center = [0.0, 10.0], radius = 10.0, from_deg = 180.0, to_deg = 360.0 }
mesh = { size = 1.0, refine = [ { near_segment = [[-0.35, 0.0], [0.35, 0.0]], size = )" +
         std::to_string(size) + R"(, radius = 0.0, growth = 1.3 } ] }
[[obstacle]]
name = "flat"
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[[plate]]
name = "cap"
on = { line = { point = [0.0, 10.0], direction = [1.0, 0.0] } }
reference = [0.0, 10.0]
fix = ["rotation"]
[[load]]
on = { line = { point = [0.0, 10.0], direction = [1.0, 0.0] } }
total_force = [0.0, -1000.0]
amplitude = [[0.0, 0.0], [0.5, 1.0], [1.0, 1.0]]
[[load]]
on = { line = { point = [0.0, 10.0], direction = [1.0, 0.0] } }
total_force = [150.0, 0.0]
amplitude = [[0.0, 0.0], [0.5, 0.0], [1.0, 1.0]]
[[contact]]
slave = { body = "cylinder", arc = { center = [0.0, 10.0], radius = 10.0, from_deg = -95.0, to_deg = -85.0 } }
master = { obstacle = "flat" }
method = "lagrange"
friction = { coefficient = 0.3 }
)";
}

}  // namespace

// The stick zone is the longest run of sticking nodes: at b/40 c/b_Hertz (stick_length / 2b)
// within 1 % of GetFEM's b/80 figure 0.4332 (0.4343 measured; GetFEM's own levels spread by
// 1.4 %). Counting every sticking node gave 0.4414 (+1.9 %): the nodes that first touch in the last
// increment have not slipped yet and stick at the contact's edge, apart from the zone.
TEST(Friction, RigidFlatCattaneoStickZoneBesideGetFEM) {
  const double b = 0.234891;  // Hertz, frictionless: √(4PR/(πE*)), E* = E/(1 − ν²)
  const core::Scene scene = core::parse_scene(rigid_flat_cattaneo(b / 40), "rigid_flat.toml");
  const test::SceneRun r = test::run_scene(scene, "lagrange");
  ASSERT_EQ(r.results.status, SolveStatus::kConverged) << r.results.message;
  EXPECT_NEAR(r.report.stick_length / (2 * b) / 0.4332, 1.0, 0.01);
  EXPECT_NEAR(r.report.resultant.x(), -150.0, 1e-6 * 1000.0);
  // the load along the flat (the curved slave's own normals tilt across the zone: -149.15)
  EXPECT_NEAR(r.report.tangent_force, -150.0, 1e-6 * 1000.0);
}
