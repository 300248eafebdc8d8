// What compare and sweep judge runs by (app/studies/study_metric.hpp): the metric chosen from
// the scene or --metric, its reading from a summary, and the observed order of convergence with
// its flags (negative, near zero, erratic).
#include "app/studies/study_metric.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/errors.hpp"
#include "core/scene.hpp"

namespace {

using namespace c2d::app;

c2d::core::Scene hertz_scene(const std::string& extra = "") {
  std::ifstream in(std::string(C2D_SOURCE_DIR) + "/examples/hertz_rigid_fast.toml");
  std::stringstream text;
  text << in.rdbuf() << extra;
  return c2d::core::parse_scene(text.str(), "hertz_rigid_fast");
}

TEST(StudyMetric, OrderOfAPowerLawIsItsExponent) {
  // e = 0.01 h^2 at h = 1, 1/2, 1/4: every level-to-level order is 2, the fit 2 to round-off.
  const ObservedOrder q = observed_order({{1.0, 0.01}, {0.5, 0.0025}, {0.25, 0.000625}});
  EXPECT_NEAR(q.order, 2.0, 1e-12);
  EXPECT_NEAR(q.low, 2.0, 1e-12);
  EXPECT_NEAR(q.high, 2.0, 1e-12);
  EXPECT_EQ(q.points, 3);
  EXPECT_TRUE(q.trusted()) << q.flag;
}

TEST(StudyMetric, ErraticNegativeAndStalledOrdersAreFlagged) {
  // The elastic block's trapezoidal-rule errors of issue 34 (0.33, 0.62, 0.30 %): level to level
  // log2(0.33/0.62) = -0.91 and log2(0.62/0.30) = 1.05; the fit's 0.07 is near zero, and a
  // "best" level chosen on it would be a lucky one.
  const ObservedOrder erratic = observed_order({{1.0, 0.0033}, {0.5, 0.0062}, {0.25, 0.0030}});
  EXPECT_NEAR(erratic.low, std::log2(0.33 / 0.62), 1e-12);
  EXPECT_NEAR(erratic.high, std::log2(0.62 / 0.30), 1e-12);
  EXPECT_FALSE(erratic.trusted());
  EXPECT_NE(erratic.flag, "");
  // Errors that grow fivefold per halving: order -log2(5) = -2.32.
  const ObservedOrder negative = observed_order({{1.0, 0.001}, {0.5, 0.005}, {0.25, 0.025}});
  EXPECT_NEAR(negative.order, -std::log2(5.0), 1e-12);
  EXPECT_EQ(negative.flag.rfind("negative", 0), 0u) << negative.flag;
  // A floor: 0.30, 0.29, 0.29 % (order 0.024).
  const ObservedOrder stalled = observed_order({{1.0, 0.0030}, {0.5, 0.0029}, {0.25, 0.0029}});
  EXPECT_EQ(stalled.flag.rfind("near zero", 0), 0u) << stalled.flag;
  // Two levels give an order without a spread; one level none.
  const ObservedOrder two = observed_order({{1.0, 0.004}, {0.5, 0.002}});
  EXPECT_NEAR(two.order, 1.0, 1e-12);
  EXPECT_TRUE(two.trusted());
  EXPECT_FALSE(observed_order({{1.0, 0.004}}).trusted());
  EXPECT_TRUE(std::isnan(observed_order({{1.0, 0.004}}).order));
}

TEST(StudyMetric, OrdersPrintWithoutNegativeZero) {
  EXPECT_EQ(order_text(-0.001), "0");
  EXPECT_EQ(order_text(1.2345), "1.23");
  EXPECT_EQ(order_text(-6.951), "-6.95");
  EXPECT_EQ(order_text(std::nan("")), "–");
}

TEST(StudyMetric, DefaultIsTheScenesReferenceAndMetricChoosesAnother) {
  const c2d::core::Scene scene = hertz_scene(
      "\n[[probe]]\nname = \"tip\"\nquantity = \"uy\"\nat = [0.0, 500.0]\n");
  const StudyMetric by_default = choose_metric(scene, "");
  EXPECT_EQ(by_default.key, "pressure_profile_l2");
  EXPECT_TRUE(by_default.reference);
  const StudyMetric pmax = choose_metric(scene, "p_max");
  EXPECT_TRUE(pmax.reference);
  EXPECT_EQ(pmax.why, "--metric");
  EXPECT_EQ(choose_metric(scene, "profile").key, "pressure_profile_l2");
  // A probe without a reference value is judged against a baseline run.
  const StudyMetric tip = choose_metric(scene, "tip");
  EXPECT_FALSE(tip.reference);
  EXPECT_THROW(choose_metric(scene, "nonsense"), c2d::InputError);
  try {
    choose_metric(scene, "nonsense");
  } catch (const c2d::InputError& e) {  // names the option and what the scene offers
    EXPECT_NE(std::string(e.what()).find("--metric"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("tip"), std::string::npos);
  }
  // study.json keeps the metric; older studies wrote "profile".
  EXPECT_EQ(StudyMetric::from_json(tip.to_json(), "study.json").key, "tip");
  EXPECT_FALSE(StudyMetric::from_json(tip.to_json(), "study.json").reference);
  EXPECT_EQ(StudyMetric::from_json("profile", "study.json").key, "pressure_profile_l2");
  EXPECT_THROW(StudyMetric::from_json("bogus", "study.json"), c2d::InputError);
}

TEST(StudyMetric, ReadingsComeFromTheSummary) {
  const nlohmann::json summary = nlohmann::json::parse(R"({
    "contact": {"p_max": 383.5, "length": 1.66, "friction": {"tangential_force": -150.0}},
    "probes": {"tip": -0.25},
    "reference": {"relative_error": {"p_max": 0.0007, "pressure_profile_l2": 0.0049}}})");
  EXPECT_DOUBLE_EQ(metric_reading(summary, {"pressure_profile_l2", true, ""}), 0.0049);
  EXPECT_DOUBLE_EQ(metric_reading(summary, {"p_max", true, ""}), 0.0007);
  EXPECT_DOUBLE_EQ(metric_reading(summary, {"p_max", false, ""}), 383.5);
  EXPECT_DOUBLE_EQ(metric_reading(summary, {"contact_length", false, ""}), 1.66);
  EXPECT_DOUBLE_EQ(metric_reading(summary, {"tangential_force", false, ""}), 150.0);
  EXPECT_DOUBLE_EQ(metric_reading(summary, {"tip", false, ""}), -0.25);
  EXPECT_TRUE(std::isnan(metric_reading(summary, {"stick_length", false, ""})));
  EXPECT_NEAR(relative_to(1.01, 1.0), 0.01, 1e-15);
  EXPECT_TRUE(std::isnan(relative_to(1.0, 0.0)));
}

}  // namespace
