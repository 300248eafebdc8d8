#include "constraints/discretization.hpp"

#include "constraints/discretizations/mortar.hpp"
#include "constraints/discretizations/node_to_node.hpp"
#include "constraints/discretizations/node_to_segment.hpp"
#include "constraints/registry.hpp"

namespace c2d::constraints {

namespace {

template <class Discretization>
DiscretizationInfo entry(std::string name, std::string summary, bool obstacles,
                         bool slave_surface) {
  return {std::move(name), std::move(summary), obstacles, slave_surface,
          [](const DiscretizationInput& in) -> std::unique_ptr<ContactDiscretization> {
            return std::make_unique<Discretization>(in);
          }};
}

}  // namespace

const std::vector<DiscretizationInfo>& discretization_registry() {
  static const std::vector<DiscretizationInfo> registry = {
      entry<NodeToSegment>("node_to_segment", "each slave node projected onto the master edges (linear or quadratic) or a rigid obstacle", true, true),
      entry<Mortar>("mortar", "segment-to-segment: the gap weighted by linear multiplier hats on the slave corner nodes and integrated over the slave surface (passes the patch test on non-matching meshes)", true, true),
      entry<NodeToNode>("node_to_node", "each slave node paired with its nearest master node along a fixed direction (the seed's gap element)", false, false),
  };
  return registry;
}

const DiscretizationInfo* find_discretization(std::string_view name) {
  return find_entry(discretization_registry(), name);
}

const std::vector<std::string>& discretization_names() {
  static const std::vector<std::string> names = entry_names(discretization_registry());
  return names;
}

std::string discretization_table_markdown() {
  std::string out = "| detection | obstacle masters | what it does |\n|---|---|---|\n";
  for (const auto& d : discretization_registry())
    out += "| `" + d.name + "` | " + (d.obstacles ? "yes" : "no") + " | " + d.summary + " |\n";
  return out;
}

std::vector<int> on_boundary(const core::Mesh& mesh, const std::vector<int>& nodes) {
  std::vector<char> boundary(mesh.nodes.size(), 0);
  for (const core::BoundaryEdge& e : mesh.boundary_edges)
    for (int n : e.nodes)
      if (n >= 0) boundary[n] = 1;
  std::vector<int> out;
  for (int n : nodes)
    if (boundary[n]) out.push_back(n);
  return out;
}

}  // namespace c2d::constraints
