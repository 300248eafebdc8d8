#include "constraints/discretization.hpp"

#include "constraints/discretizations/node_to_node.hpp"
#include "constraints/discretizations/node_to_segment.hpp"

namespace c2d::constraints {

namespace {

template <class Discretization>
DiscretizationInfo entry(std::string name, std::string summary, bool obstacles) {
  return {std::move(name), std::move(summary), obstacles,
          [](const DiscretizationInput& in) -> std::unique_ptr<ContactDiscretization> {
            return std::make_unique<Discretization>(in);
          }};
}

}  // namespace

const std::vector<DiscretizationInfo>& discretization_registry() {
  static const std::vector<DiscretizationInfo> registry = {
      entry<NodeToSegment>("node_to_segment", "each slave node projected onto the master edges (linear or quadratic) or a rigid obstacle", true),
      entry<NodeToNode>("node_to_node", "each slave node paired with its nearest master node along a fixed direction (the seed's gap element)", false),
  };
  return registry;
}

const DiscretizationInfo* find_discretization(std::string_view name) {
  for (const auto& d : discretization_registry())
    if (d.name == name) return &d;
  return nullptr;
}

const std::vector<std::string>& discretization_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const auto& d : discretization_registry()) out.push_back(d.name);
    return out;
  }();
  return names;
}

std::string discretization_table_markdown() {
  std::string out = "| detection | obstacle masters | what it does |\n|---|---|---|\n";
  for (const auto& d : discretization_registry())
    out += "| `" + d.name + "` | " + (d.obstacles ? "yes" : "no") + " | " + d.summary + " |\n";
  return out;
}

}  // namespace c2d::constraints
