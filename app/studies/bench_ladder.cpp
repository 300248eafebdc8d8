// The bench's ladder: which scenes, elements, methods and mesh scales `contact2d bench` runs
// (full and --quick), each case's overrides, and the mesh scales that bring a scene to a number
// of DOFs.
#include <cmath>
#include <string>
#include <vector>

#include "app/studies/bench.hpp"
#include "constraints/method_registry.hpp"

namespace c2d::app {
namespace {

// Mesh scales that bring each scene to about 10k, 100k and 1M DOFs: DOFs go as base / scale²,
// with the base fitted to measured ladders (the refinement zones scale less than the rest, so
// the base is below the DOFs at scale 1: cantilever T3 1,004 and T6 3,760 DOFs at scale 1,
// 773,776 and 829,482 at 1 / sqrt(1e6 / base) with the scale-1 base). The DOFs each run
// measures are what the tables report.
struct Family {
  const char* family;
  const char* scene;
  const char* element;
  double base_dofs;
};
constexpr Family kFamilies[] = {
    {"elasticity", "cantilever.toml", "T3", 780},
    {"elasticity", "cantilever.toml", "T6", 3120},
    {"hertz_rigid", "hertz_rigid.toml", "T3", 5300},
    {"hertz_rigid", "hertz_rigid.toml", "T6", 21500},
    {"hertz_block", "hertz_block.toml", "T3", 10000},
    {"hertz_block", "hertz_block.toml", "T6", 39000},
};

double scale_for(double base_dofs, double dofs) { return std::sqrt(base_dofs / dofs); }

/// Every case: charts off (pictures for people, not a solver phase). The Hertz ladder narrows
/// the slave arc to the 4.4 mm (2.6 b) that can touch: the same physics with fewer rows.
std::vector<std::string> case_sets(const std::string& family) {
  std::vector<std::string> s{"output.charts=false"};
  if (family == "hertz_rigid" || family == "hertz_block")
    s.push_back("contact.slave.arc.from_deg=-90.5");
  return s;
}

}  // namespace

std::vector<BenchCase> bench_ladder(bool quick) {
  std::vector<BenchCase> cases;
  auto add = [&](const std::string& family, const std::string& scene, const std::string& element,
                 const std::string& method, double scale, const std::string& nominal) {
    BenchCase c{family, scene, element, method, scale, nominal, case_sets(family)};
    cases.push_back(c);
  };
  if (quick) {
    add("elasticity", "cantilever.toml", "T6", "", 1.0, "4k");
    add("elasticity", "cantilever.toml", "T6", "", 0.5, "15k");
    add("hertz_rigid", "hertz_rigid.toml", "T6", "lagrange", 4.0, "4k");
    add("hertz_rigid", "hertz_rigid.toml", "T6", "lagrange", 2.0, "9k");
    add("two_cantilevers", "two_cantilevers.toml", "T6", "lagrange", 2.0, "3k");
    add("stepped", "drag.toml", "T6", "lagrange", 1.0, "as shipped");
  } else {
    for (const auto& f : kFamilies)
      for (const auto& [dofs, nominal] :
           {std::pair{1e4, "10k"}, std::pair{1e5, "100k"}, std::pair{1e6, "1M"}}) {
        // Contact rungs run both exact active-set methods: the overhead target is for both.
        const bool contact = std::string(f.family) != "elasticity";
        for (const char* method : contact ? std::vector<const char*>{"lagrange", "ssn"}
                                          : std::vector<const char*>{""})
          add(f.family, f.scene, f.element, method, scale_for(f.base_dofs, dofs), nominal);
      }
    add("two_cantilevers", "two_cantilevers.toml", "T6", "lagrange", scale_for(11380, 1e4), "10k");
    add("two_cantilevers", "two_cantilevers.toml", "T6", "lagrange", scale_for(11380, 1e5), "100k");
    // Load-stepped contact with every method: large sliding with friction (drag), a slender
    // beam laid onto a floor (its surface-last ordering's fill), and Cattaneo–Mindlin with the
    // exact methods (the issue's ≤ 4 Newton iterations and factorisations per step).
    for (const char* scene : {"drag.toml", "slender_floor.toml"})
      for (const auto& m : constraints::method_names())
        add("stepped", scene, "T6", m, 1.0, "as shipped");
    for (const char* m : {"lagrange", "ssn"})
      add("stepped", "cattaneo_mindlin.toml", "T6", m, 1.0, "as shipped");
  }
  // Every method on the scenes meshed for time to accuracy, as shipped and (full ladder) refined
  // once more; the shipped lagrange runs are the time-to-accuracy figures.
  const std::vector<double> levels =
      quick ? std::vector<double>{1.0} : std::vector<double>{1.0, 0.5};
  for (const char* scene : {"hertz_rigid_fast.toml", "hertz_block_fast.toml"}) {
    for (double scale : levels)
      for (const auto& m : constraints::method_names()) {
        BenchCase c{"methods",
                    scene,
                    "T6",
                    m,
                    scale,
                    scale == 1.0 ? "as shipped" : "refined",
                    {"output.charts=false", "output.fields=false"}};
        cases.push_back(c);
      }
  }
  return cases;
}

}  // namespace c2d::app
