#include "core/structured_grid.hpp"

namespace c2d::core {

StructuredGrid make_structured_grid(int n, int order) { return make_structured_grid(n, n, order); }

StructuredGrid make_structured_grid(int nx, int ny, int order) {
  StructuredGrid g;
  Mesh& m = g.mesh;
  m.order = order;
  const int k = order * nx + 1, ky = order * ny + 1;  // nodes along x and y
  for (int j = 0; j < ky; ++j)
    for (int i = 0; i < k; ++i)
      m.nodes.emplace_back(static_cast<double>(i) / (ky - 1), static_cast<double>(j) / (ky - 1));
  auto id = [k](int i, int j) { return j * k + i; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int s = order;
      const int a = id(s * i, s * j), b = id(s * i + s, s * j), c = id(s * i + s, s * j + s), d = id(s * i, s * j + s);
      if (order == 1) {
        m.elements.push_back({a, b, c, -1, -1, -1});
        m.elements.push_back({a, c, d, -1, -1, -1});
      } else {
        const int ab = id(s * i + 1, s * j), bc = id(s * i + 2, s * j + 1), ac = id(s * i + 1, s * j + 1);
        const int cd = id(s * i + 1, s * j + 2), da = id(s * i, s * j + 1);
        m.elements.push_back({a, b, c, ab, bc, ac});
        m.elements.push_back({a, c, d, ac, cd, da});
      }
      m.element_body.insert(m.element_body.end(), {0, 0});
      m.element_material.insert(m.element_material.end(), {0, 0});
    }
  g.dofs = DofMap(m.num_dofs());
  for (int j = 0; j < ky; ++j) {
    g.dofs.constrain(2 * id(0, j), 0.0);
    g.dofs.constrain(2 * id(0, j) + 1, 0.0);
  }
  g.dofs.finalize();
  g.material.young = 210000;
  g.material.poisson = 0.3;
  g.material.state = PlaneState::kPlaneStrain;
  return g;
}

}  // namespace c2d::core
