#include "core/springs.hpp"

#include <Eigen/Dense>

namespace c2d::core {

namespace {

/// A spring's force on its nodes (a, then b) and its 4 × 4 (node to node) or 2 × 2 (to ground)
/// stiffness at u.
struct SpringState {
  Eigen::Vector4d f = Eigen::Vector4d::Zero();
  Eigen::Matrix4d k = Eigen::Matrix4d::Zero();
  double axial = 0.0;
};

SpringState evaluate(const Model& model, const Spring& s, const VecX& u, bool finite_strain) {
  SpringState out;
  const Vec2 ua = u.segment<2>(2 * s.a);
  if (s.b < 0) {
    out.f.head<2>() = s.k_ground.cwiseProduct(ua);
    out.k.topLeftCorner<2, 2>() = s.k_ground.asDiagonal();
    out.axial = out.f.head<2>().norm();
    return out;
  }
  const Vec2 d0 = model.mesh.nodes[s.b] - model.mesh.nodes[s.a];
  const Vec2 du = u.segment<2>(2 * s.b) - ua;
  Eigen::Matrix2d kbb;
  Vec2 fb;
  if (!finite_strain) {
    const Vec2 e = d0.normalized();
    kbb = s.k * e * e.transpose();
    fb = kbb * du;
    out.axial = s.k * e.dot(du);
  } else {
    const Vec2 d = d0 + du;
    const double length = d.norm(), rest = d0.norm();
    const Vec2 e = d / length;
    const double n = s.k * (length - rest);
    kbb = s.k * e * e.transpose() + (n / length) * (Eigen::Matrix2d::Identity() - e * e.transpose());
    fb = n * e;
    out.axial = n;
  }
  out.f << -fb, fb;
  out.k << kbb, -kbb, -kbb, kbb;
  return out;
}

}  // namespace

void add_spring_forces(const Model& model, const VecX& u, bool finite_strain, VecX& f) {
  for (const Spring& s : model.springs) {
    const SpringState st = evaluate(model, s, u, finite_strain);
    f.segment<2>(2 * s.a) += st.f.head<2>();
    if (s.b >= 0) f.segment<2>(2 * s.b) += st.f.tail<2>();
  }
}

SpMat spring_stiffness(const Model& model, const VecX& u, bool finite_strain,
                       const VecX* du_constrained, VecX* lift) {
  const DofMap& dofs = model.dofs;
  std::vector<Triplet> t;
  for (const Spring& s : model.springs) {
    const SpringState st = evaluate(model, s, u, finite_strain);
    const int nodes[2] = {s.a, s.b};
    const int count = s.b < 0 ? 2 : 4;
    for (int i = 0; i < count; ++i) {
      const int ei = dofs.equation(2 * nodes[i / 2] + i % 2);
      if (ei < 0) continue;
      for (int j = 0; j < count; ++j) {
        const int dof_j = 2 * nodes[j / 2] + j % 2, ej = dofs.equation(dof_j);
        if (ej >= 0)
          t.emplace_back(ei, ej, st.k(i, j));
        else if (du_constrained && lift)
          (*lift)[ei] += st.k(i, j) * (*du_constrained)[dof_j];
      }
    }
  }
  SpMat k(dofs.num_free(), dofs.num_free());
  k.setFromTriplets(t.begin(), t.end());
  return k;
}

double spring_force(const Model& model, const Spring& s, const VecX& u, bool finite_strain) {
  return evaluate(model, s, u, finite_strain).axial;
}

}  // namespace c2d::core
