#include "constraints/contact_scene.hpp"

#include <algorithm>


#include "constraints/discretization.hpp"
#include "constraints/method_registry.hpp"
#include "core/errors.hpp"
#include "core/toml_view.hpp"

namespace c2d::constraints {

using core::TomlView;

namespace {

Obstacle parse_obstacle(const TomlView& v) {
  Obstacle o;
  o.name = v["name"].string();
  const std::string type = v["type"].choice({"line", "circle"});
  if (type == "line") {
    v.check_keys({"name", "type", "point", "normal"});
    o.type = Obstacle::Type::kLine;
    o.point = v["point"].vec2();
    o.normal = v["normal"].vec2();
    if (o.normal.norm() == 0) v["normal"].fail("a non-zero normal pointing toward the bodies");
    o.normal.normalize();
  } else {
    v.check_keys({"name", "type", "center", "radius", "inside"});
    o.type = Obstacle::Type::kCircle;
    o.center = v["center"].vec2();
    o.radius = v["radius"].positive();
    o.inside = v["inside"].boolean_or(false);
  }
  return o;
}

void parse_options(const TomlView& v, StrategyOptions& o) {
  o.method = v["method"].choice_or(method_names(), o.method);
  if (v.has("penalty")) {
    const TomlView p = v["penalty"];
    p.require_table();
    p.check_keys({"k", "factor", "growth", "max_factor"});
    if (p.has("k")) o.penalty_k = p["k"].positive();
    if (p.has("factor")) o.penalty_factor = p["factor"].positive();
    if (p.has("growth")) {
      o.penalty_growth = p["growth"].number();
      if (!(o.penalty_growth > 1)) p["growth"].fail("a growth factor > 1");
    }
    if (p.has("max_factor")) o.max_penalty_factor = p["max_factor"].positive();
  }
  if (v.has("auglag")) {
    const TomlView a = v["auglag"];
    a.require_table();
    a.check_keys({"factor"});
    o.augmentation_factor = a["factor"].positive();
  }
  if (v.has("ipopt")) {
    const TomlView i = v["ipopt"];
    i.require_table();
    i.check_keys({"tol"});
    o.ipopt_tolerance = i["tol"].positive();
  }
  if (v.has("tolerance")) o.tolerance = v["tolerance"].positive();
  if (v.has("relative_tolerance")) o.relative_tolerance = v["relative_tolerance"].positive();
  if (v.has("penetration_limit")) o.penetration_limit = v["penetration_limit"].positive();
  if (v.has("max_iterations")) {
    o.max_iterations = v["max_iterations"].integer();
    if (o.max_iterations < 1) v["max_iterations"].fail("an integer >= 1");
  }
}

EqualitySpec parse_equality(const TomlView& v, int index) {
  EqualitySpec e;
  e.where = v.where();
  e.name = v["name"].string_or("constraint" + std::to_string(index + 1));
  e.type = v["type"].choice(equality_names());
  const EqualityInfo* info = find_equality(e.type);
  std::vector<std::string> keys = {"name",      "type",      "method",
                                   "penalty",   "auglag",    "ipopt",
                                   "tolerance", "relative_tolerance", "max_iterations",
                                   "penetration_limit"};
  keys.insert(keys.end(), info->key_names.begin(), info->key_names.end());
  v.check_keys(keys);
  e.constraint = info->parse(v);
  return e;
}

}  // namespace

namespace {

/// The law a `friction` table names: its `law`, or the law whose keys it gives, exactly.
const FrictionLawInfo& friction_law_of(const TomlView& v) {
  if (v.has("law")) return *find_friction_law(v["law"].choice(friction_law_names()));
  std::vector<std::string> keys = {"law", "penalty_ratio"}, given;
  for (const auto& law : friction_law_registry())
    for (const std::string& k : law.key_names)
      if (std::find(keys.begin(), keys.end(), k) == keys.end()) {
        keys.push_back(k);
        if (v.has(k)) given.push_back(k);
      }
  v.check_keys(keys);
  std::string options;
  for (const auto& law : friction_law_registry()) {
    std::vector<std::string> own = law.key_names;
    std::sort(own.begin(), own.end());
    std::sort(given.begin(), given.end());
    if (own == given) return law;
    std::string list;
    for (const std::string& k : law.key_names) list.append(list.empty() ? "" : " and ").append(k);
    options.append(options.empty() ? "" : ", ").append(list).append(" (").append(law.name).append(")");
  }
  v.fail("a `law` or the keys of one: " + options);
}

FrictionSpec parse_friction(const TomlView& v, const ContactPairSpec& c) {
  v.require_table();
  const FrictionLawInfo& law = friction_law_of(v);
  std::vector<std::string> keys = {"law", "penalty_ratio"};
  keys.insert(keys.end(), law.key_names.begin(), law.key_names.end());
  v.check_keys(keys);
  FrictionSpec f;
  f.law = law.name;
  f.model = law.parse(v);
  if (law.traction && c.detection == "node_to_node")
    v.fail("a law without a traction bound (" + law.name + " bounds the shear traction, and "
           "node_to_node has no slave surface to spread it over)");
  if (v.has("penalty_ratio")) f.penalty_ratio = v["penalty_ratio"].positive();
  return f;
}

}  // namespace

ContactSceneSpec parse_contact_scene(const core::Scene& scene, const std::string& method) {
  ContactSceneSpec spec;
  if (scene.explicit_model) {
    // The seed's gap elements: node_to_node pairs built by ContactPairs from the legacy model.
    spec.options.method = "penalty";
  } else if (scene.raw) {
    const TomlView root(scene.raw.get(), "", &scene.path);
    for (const auto& v : root["obstacle"].tables()) {
      Obstacle o = parse_obstacle(v);
      for (const auto& other : spec.obstacles)
        if (other.name == o.name) v["name"].fail("a unique obstacle name");
      spec.obstacles.push_back(o);
    }
    // One solve enforces every contact and constraint the same way: the first table that
    // sets the method's options sets them for all, a later one may only repeat its method.
    bool first = true;
    std::string first_kind;
    auto adopt_options = [&](const TomlView& v, const std::string& table) {
      StrategyOptions o = spec.options;
      parse_options(v, o);
      if (!first && v.has("method") && o.method != spec.options.method)
        v["method"].fail("the same method as the first " + first_kind + " ('" +
                         spec.options.method +
                         "'): one solve enforces every contact and constraint alike");
      if (first) spec.options = o, first_kind = table;
      first = false;
    };
    for (const auto& v : root["contact"].tables()) {
      v.check_keys({"name", "slave", "master", "detection", "direction", "search_distance",
                    "method", "penalty", "auglag", "ipopt", "tolerance", "relative_tolerance",
                    "max_iterations", "penetration_limit", "friction"});
      ContactPairSpec c;
      c.where = v.where();
      c.name = v["name"].string_or("contact" + std::to_string(spec.pairs.size() + 1));
      for (const auto& other : spec.pairs)
        if (other.name == c.name) v["name"].fail("a unique [[contact]] name");
      c.slave = core::parse_selection(v["slave"]);
      const TomlView m = v["master"];
      m.require_table();
      if (m.has("obstacle")) {
        m.check_keys({"obstacle"});
        const std::string name = m["obstacle"].string();
        std::vector<std::string> names;
        for (size_t i = 0; i < spec.obstacles.size(); ++i) {
          names.push_back(spec.obstacles[i].name);
          if (spec.obstacles[i].name == name) c.obstacle = static_cast<int>(i);
        }
        if (c.obstacle < 0)
          m["obstacle"].fail("the name of an [[obstacle]]" + core::did_you_mean(name, names));
      } else {
        c.master = core::parse_selection(m);
      }
      c.detection = v["detection"].choice_or(discretization_names(), c.detection);
      if (c.obstacle >= 0 && !find_discretization(c.detection)->obstacles)
        v["detection"].fail("a detection that takes an obstacle master");
      if (v.has("direction")) {
        // Only node_to_node pairs along a fixed direction; the others ignored it without a word.
        if (c.detection != "node_to_node")
          v["direction"].fail_message("expected no direction with detection = \"" + c.detection +
                                      "\" (a fixed direction pairs nodes for detection = "
                                      "\"node_to_node\" only), found one");
        c.direction = v["direction"].vec2();
        if (c.direction->norm() == 0) v["direction"].fail("a non-zero direction");
        c.direction->normalize();
      }
      if (v.has("search_distance")) c.search_distance = v["search_distance"].positive();
      if (v.has("friction")) c.friction = parse_friction(v["friction"], c);
      adopt_options(v, "[[contact]]");
      spec.pairs.push_back(c);
    }
    for (const auto& v : root["constraint"].tables()) {
      EqualitySpec e = parse_equality(v, static_cast<int>(spec.equalities.size()));
      for (const auto& other : spec.equalities)
        if (other.name == e.name) v["name"].fail("a unique [[constraint]] name");
      adopt_options(v, "[[constraint]]");
      spec.equalities.push_back(e);
    }
  }
  if (!method.empty()) spec.options.method = method;
  if (const std::string error = spec.options.validate(); !error.empty())
    throw InputError(scene.path + ": contact " + error);
  return spec;
}

}  // namespace c2d::constraints
