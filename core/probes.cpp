#include "core/probes.hpp"

#include <cmath>

#include "core/errors.hpp"
#include "core/triangle.hpp"

namespace c2d::core {

double point_quantity(const std::string& q, const Vec2& u, const Vec2& reaction, const Voigt& s,
                      const Material& material) {
  if (q == "ux") return u.x();
  if (q == "uy") return u.y();
  if (q == "umag") return u.norm();
  if (q == "reaction_x") return reaction.x();
  if (q == "reaction_y") return reaction.y();
  if (q == "sx") return s[0];
  if (q == "sy") return s[1];
  if (q == "sxy") return s[2];
  if (q == "s1") return principal(s)[0];
  if (q == "s2") return principal(s)[1];
  if (q == "vm") return von_mises(s, material.sigma_zz(s));
  return std::nan("");
}

double nodal_quantity(const Model& model, const Results& r, const std::string& q, int n) {
  return point_quantity(q, r.displacement.segment<2>(2 * n), r.reaction.segment<2>(2 * n),
                        r.nodal_stress.col(n),
                        model.materials[model.node_material.empty() ? 0 : model.node_material[n]]);
}

std::map<std::string, double> evaluate_probes(const Scene& scene, const Model& model,
                                              const Results& results) {
  std::map<std::string, double> out;
  const Mesh& mesh = model.mesh;
  std::unique_ptr<PointLocator> locator;
  for (const auto& p : scene.probes) {
    double value = 0.0;
    if (!p.plate.empty()) {
      // A plate's motion or transmitted force, kept by the constrained solve.
      const auto it = results.globals.find(p.quantity + "/" + p.plate);
      value = it != results.globals.end() ? it->second : 0.0;
    } else if (!p.point && !p.on) {
      // A global quantity of the analysis (contact_pressure_max, ...): 0 when absent.
      const auto it = results.globals.find(p.quantity);
      value = it != results.globals.end() ? it->second : 0.0;
    } else if (p.point) {
      if (!locator) locator = std::make_unique<PointLocator>(mesh);
      const auto hit = locator->locate(*p.point);
      if (hit.element < 0)
        throw InputError(p.at.where + ": probe point (" + number_text(p.point->x()) + ", " +
                         number_text(p.point->y()) + ") lies outside the mesh");
      const int nn = mesh.nodes_per_element();
      Eigen::VectorXd n(nn);
      if (nn == 3)
        n = T3::shape(hit.a, hit.b);
      else
        n = T6::shape(hit.a, hit.b);
      // Interpolate the nodal fields (displacement; smoothed stress) with the element's shape
      // functions, then derive the requested quantity.
      Vec2 u = Vec2::Zero();
      Voigt s = Voigt::Zero();
      for (int i = 0; i < nn; ++i) {
        const int node = mesh.elements[hit.element][i];
        u += n[i] * results.displacement.segment<2>(2 * node);
        s += n[i] * results.nodal_stress.col(node);
      }
      value = point_quantity(p.quantity, u, Vec2::Zero(), s,
                             model.materials[mesh.element_material[hit.element]]);
    } else {
      const auto nodes = select_nodes(model, *p.on);
      double acc = p.reduce == "max" ? -1e300 : p.reduce == "min" ? 1e300 : 0.0;
      double best_abs = -1.0;
      for (int node : nodes) {
        const double v = nodal_quantity(model, results, p.quantity, node);
        if (p.reduce == "max") acc = std::max(acc, v);
        else if (p.reduce == "min") acc = std::min(acc, v);
        else if (p.reduce == "sum" || p.reduce == "mean") acc += v;
        else if (std::abs(v) > best_abs) best_abs = std::abs(v), acc = v;  // maxabs, value
      }
      if (p.reduce == "mean") acc /= static_cast<double>(nodes.size());
      value = acc;
    }
    out[p.name] = value;
  }
  return out;
}

}  // namespace c2d::core
