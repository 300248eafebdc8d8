// What a study judges its runs by: compare's and sweep's --metric. Either a relative error the
// runs report against the scene's [reference] (the pressure profile, p_max, a probe with a
// reference value, ...), or a quantity the scene has no reference for (a probe, the stick
// length), judged against a baseline run of the same study: compare's exact method on the
// finest level, sweep's exact method on the same mesh.
#pragma once

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "core/scene.hpp"

namespace c2d::app {

struct StudyMetric {
  /// A key of summary.json's reference.relative_error (pressure_profile_l2, shear_profile_l2,
  /// p_max, contact_length, total_force, stick_length, tangential_force, a probe's name), or,
  /// without a reference, a quantity: one of those contact figures or a probe's name.
  std::string key;
  /// True: the run's relative error against the reference. False: the run's value, judged by
  /// its relative difference from a baseline run's.
  bool reference = false;
  std::string why;  ///< how it was chosen ("--metric", or the default's reason)

  bool empty() const { return key.empty(); }
  /// The metric in words, for verdicts and axis labels.
  std::string label() const;
  nlohmann::json to_json() const;
  /// From study.json (also the older form: "profile", "shear", "p_max" or ""); `where` names
  /// the file for errors.
  static StudyMetric from_json(const nlohmann::json& options, const std::string& where);
};

/// The metric `asked` for (--metric; empty: the scene's default: its Hertz profile, its
/// Cattaneo–Mindlin shear profile, its p_max reference, else none). Throws InputError naming
/// --metric and the keys this scene offers when `asked` is none of them.
StudyMetric choose_metric(const core::Scene& scene, const std::string& asked);

/// A converged run's reading of the metric from its summary.json: the relative error (reference
/// metrics) or the value (NaN when the run does not report it).
double metric_reading(const nlohmann::json& summary, const StudyMetric& metric);

/// The relative difference of `value` from `baseline` (NaN unless both are finite and the
/// baseline is not 0).
double relative_to(double value, double baseline);

}  // namespace c2d::app

namespace c2d::app {

/// The observed order of convergence of one method's errors under refinement, and whether it
/// can be trusted.
struct ObservedOrder {
  double order = std::nan("");  ///< least-squares slope of log(error) against log(h)
  double low = std::nan(""), high = std::nan("");  ///< the level-to-level orders' extremes
  int points = 0;     ///< levels with an error above 0
  std::string flag;   ///< "" or why the order is not to be trusted (negative, near zero, erratic)
  bool trusted() const { return points >= 2 && flag.empty(); }
};

/// From (h, error) pairs, h ∝ the element size (any order; errors ≤ 0 or not finite skipped).
ObservedOrder observed_order(std::vector<std::pair<double, double>> h_error);

/// An order as the tables print it: two decimals, never "-0".
std::string order_text(double order);

}  // namespace c2d::app
