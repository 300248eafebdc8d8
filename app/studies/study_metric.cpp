#include "app/studies/study_metric.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "app/report/hertz.hpp"
#include "app/studies/study.hpp"
#include "core/errors.hpp"

namespace c2d::app {

namespace {

/// The contact figures a run reports, as reference keys and summary.json paths.
struct Figure {
  const char* key;
  std::vector<const char*> path;
  const char* words;
};
const Figure kFigures[] = {
    {"p_max", {"contact", "p_max"}, "p_max"},
    {"contact_length", {"contact", "length"}, "the contact length"},
    {"total_force", {"contact", "total_force"}, "the total contact force"},
    {"stick_length", {"contact", "friction", "stick_length"}, "the stick zone's length"},
    {"tangential_force", {"contact", "friction", "tangential_force"}, "the tangential force"},
};

const Figure* figure(const std::string& key) {
  for (const Figure& f : kFigures)
    if (key == f.key) return &f;
  return nullptr;
}

bool is_probe(const core::Scene& scene, const std::string& key) {
  for (const core::ProbeSpec& p : scene.probes)
    if (p.name == key) return true;
  return false;
}

/// The keys the runs of `scene` report a relative error for.
std::set<std::string> reference_keys(const core::Scene& scene) {
  std::set<std::string> keys;
  for (const auto& [key, value] : scene.reference)
    if (value != 0 && (figure(key) || is_probe(scene, key))) keys.insert(key);
  if (hertz_reference(scene)) keys.insert({"pressure_profile_l2", "pressure_profile_inner_l2"});
  if (cattaneo_reference(scene)) keys.insert("shear_profile_l2");
  return keys;
}

std::string canonical(const std::string& key) {
  return key == "profile" ? "pressure_profile_l2"
         : key == "inner" ? "pressure_profile_inner_l2"
         : key == "shear" ? "shear_profile_l2"
                          : key;
}

std::string words(const std::string& key) {
  if (key == "pressure_profile_l2") return "the pressure profile";
  if (key == "pressure_profile_inner_l2") return "the pressure profile inside 0.9 b";
  if (key == "shear_profile_l2") return "the shear profile (Cattaneo–Mindlin)";
  if (const Figure* f = figure(key)) return f->words;
  return "probe " + key;
}

}  // namespace

std::string StudyMetric::label() const {
  if (key == "pressure_profile_l2" || key == "pressure_profile_inner_l2" ||
      key == "shear_profile_l2")
    return "relative L2 error of " + words(key);
  return reference ? "relative error of " + words(key)
                   : "relative difference of " + words(key) + " from the baseline's";
}

nlohmann::json StudyMetric::to_json() const {
  return {{"key", key}, {"reference", reference}, {"why", why}};
}

StudyMetric StudyMetric::from_json(const nlohmann::json& j, const std::string& where) {
  StudyMetric m;
  if (j.is_string()) {  // study.json before --metric: "profile", "shear", "p_max" or ""
    const std::string old = j.get<std::string>();
    if (old != "" && old != "profile" && old != "shear" && old != "p_max")
      throw InputError(where + ": options.metric: expected profile, shear, p_max or \"\", found '" +
                       old + "'");
    m.key = canonical(old);
    m.reference = !old.empty();
    m.why = "the scene's reference";
    return m;
  }
  if (!j.is_object() || !j.contains("key") || !j["key"].is_string() || !j.contains("reference") ||
      !j["reference"].is_boolean())
    throw InputError(where + ": options.metric: expected {key, reference, why}, found " +
                     j.dump().substr(0, 60));
  m.key = j["key"].get<std::string>();
  m.reference = j["reference"].get<bool>();
  if (j.contains("why") && j["why"].is_string()) m.why = j["why"].get<std::string>();
  return m;
}

StudyMetric choose_metric(const core::Scene& scene, const std::string& asked) {
  const std::set<std::string> refs = reference_keys(scene);
  StudyMetric m;
  if (asked.empty()) {
    // A frictional Hertz case (Cattaneo–Mindlin) is judged on its shear profile, which depends
    // on the stick and slip zones as well as the pressure.
    m.key = hertz_reference(scene)              ? "pressure_profile_l2"
            : refs.count("shear_profile_l2")    ? "shear_profile_l2"
            : refs.count("p_max")               ? "p_max"
                                                : "";
    m.reference = !m.key.empty();
    m.why = m.key.empty() ? "the scene has no reference" : "the scene's reference, by default";
    return m;
  }
  m.key = canonical(asked);
  m.why = "--metric";
  m.reference = refs.count(m.key) > 0;
  if (m.reference || figure(m.key) || is_probe(scene, m.key)) return m;
  std::string offered;
  for (const std::string& k : refs) offered += (offered.empty() ? "" : ", ") + k;
  for (const Figure& f : kFigures)
    if (!refs.count(f.key)) offered += std::string(", ") + f.key;
  for (const core::ProbeSpec& p : scene.probes)
    if (!refs.count(p.name)) offered += ", " + p.name;
  throw InputError("--metric: expected a reference key, a contact figure or a probe of this "
                   "scene (" + offered + "), found '" + asked + "'");
}

double metric_reading(const nlohmann::json& summary, const StudyMetric& m) {
  if (m.reference) return json_number(summary, {"reference", "relative_error", m.key.c_str()});
  if (const Figure* f = figure(m.key)) {
    const nlohmann::json* node = &summary;
    for (const char* k : f->path) {
      if (!node->is_object() || !node->contains(k)) return std::nan("");
      node = &(*node)[k];
    }
    if (!node->is_number()) return std::nan("");
    return m.key == "tangential_force" ? std::abs(node->get<double>()) : node->get<double>();
  }
  return json_number(summary, {"probes", m.key.c_str()});
}

double relative_to(double value, double baseline) {
  if (!std::isfinite(value) || !std::isfinite(baseline) || baseline == 0) return std::nan("");
  return value / baseline - 1.0;
}

}  // namespace c2d::app

namespace c2d::app {

namespace {

/// Orders below this are "near zero": the error has stopped falling.
constexpr double kStalledOrder = 0.25;
/// Level-to-level orders further apart than this are "erratic" (the error falls by luck at
/// one level, e.g. where the contact's edge meets a node, and not at the next).
constexpr double kErraticSpread = 1.5;

}  // namespace

ObservedOrder observed_order(std::vector<std::pair<double, double>> h_error) {
  ObservedOrder q;
  std::vector<std::pair<double, double>> pts;  // (log h, log e), coarse to fine
  for (const auto& [h, e] : h_error)
    if (h > 0 && std::isfinite(e) && e > 0) pts.emplace_back(std::log(h), std::log(e));
  std::sort(pts.begin(), pts.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  q.points = static_cast<int>(pts.size());
  if (q.points < 2) return q;
  double mx = 0, my = 0;
  for (const auto& [x, y] : pts) mx += x, my += y;
  mx /= q.points, my /= q.points;
  double sxy = 0, sxx = 0;
  for (const auto& [x, y] : pts) sxy += (x - mx) * (y - my), sxx += (x - mx) * (x - mx);
  if (!(sxx > 0)) return q;
  q.order = sxy / sxx;
  for (size_t i = 1; i < pts.size(); ++i) {
    const double pair = (pts[i - 1].second - pts[i].second) / (pts[i - 1].first - pts[i].first);
    q.low = std::isfinite(q.low) ? std::min(q.low, pair) : pair;
    q.high = std::isfinite(q.high) ? std::max(q.high, pair) : pair;
  }
  if (q.order < -0.1)
    q.flag = "negative: the error grows under refinement";
  else if (q.order < kStalledOrder)
    q.flag = "near zero: the error does not fall under refinement";
  else if (q.points >= 3 && (q.low < 0 || q.high - q.low > kErraticSpread))
    q.flag = "erratic: level-to-level orders from " + order_text(q.low) + " to " +
             order_text(q.high);
  return q;
}

std::string order_text(double order) {
  if (!std::isfinite(order)) return "–";
  const double rounded = std::round(order * 100) / 100;
  return csv_number(rounded == 0 ? 0.0 : rounded);  // never "-0"
}

}  // namespace c2d::app
