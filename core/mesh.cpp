#include "core/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "core/triangle.hpp"

#include <Eigen/LU>

namespace c2d::core {

double Mesh::corner_area(int e) const {
  const auto& n = elements[e];
  const Vec2 a = nodes[n[1]] - nodes[n[0]], b = nodes[n[2]] - nodes[n[0]];
  return 0.5 * (a.x() * b.y() - a.y() * b.x());
}

int Mesh::orient_counter_clockwise() {
  int flipped = 0;
  for (int e = 0; e < num_elements(); ++e) {
    if (corner_area(e) < 0.0) {
      auto& n = elements[e];
      std::swap(n[1], n[2]);
      if (order == 2) std::swap(n[3], n[5]);  // edges 0-1 and 2-0 trade places
      ++flipped;
    }
  }
  return flipped;
}

void Mesh::build_boundary() {
  boundary_edges.clear();
  struct Use {
    int element, local, count;
  };
  std::unordered_map<long long, Use> uses;
  uses.reserve(elements.size() * 2);
  const long long n = num_nodes();
  for (int e = 0; e < num_elements(); ++e) {
    for (int k = 0; k < 3; ++k) {
      const int i = elements[e][k], j = elements[e][(k + 1) % 3];
      const long long key = std::min(i, j) * n + std::max(i, j);
      auto [it, inserted] = uses.try_emplace(key, Use{e, k, 0});
      it->second.count++;
    }
  }
  std::vector<std::pair<int, int>> found;  // (element, local edge), sorted for determinism
  for (const auto& [key, use] : uses)
    if (use.count == 1) found.emplace_back(use.element, use.local);
  std::sort(found.begin(), found.end());
  for (auto [e, k] : found) {
    BoundaryEdge be;
    be.nodes[0] = elements[e][k];
    be.nodes[1] = elements[e][(k + 1) % 3];
    if (order == 2) be.nodes[2] = elements[e][3 + k];
    be.element = e;
    be.body = element_body[e];
    boundary_edges.push_back(be);
  }
}

Eigen::MatrixX2d Mesh::element_coords(int e) const {
  const int nn = nodes_per_element();
  Eigen::MatrixX2d x(nn, 2);
  for (int i = 0; i < nn; ++i) x.row(i) = nodes[elements[e][i]].transpose();
  return x;
}

void Mesh::append(const Mesh& other, int body_offset, int material_offset,
                  const std::string& prefix) {
  const int node_offset = num_nodes();
  const int edge_offset = static_cast<int>(boundary_edges.size());
  nodes.insert(nodes.end(), other.nodes.begin(), other.nodes.end());
  for (int e = 0; e < other.num_elements(); ++e) {
    auto conn = other.elements[e];
    for (int i = 0; i < other.nodes_per_element(); ++i) conn[i] += node_offset;
    elements.push_back(conn);
    element_body.push_back(other.element_body[e] + body_offset);
    element_material.push_back(other.element_material[e] + material_offset);
  }
  const int element_offset = num_elements() - other.num_elements();
  for (auto be : other.boundary_edges) {
    for (int& v : be.nodes)
      if (v >= 0) v += node_offset;
    be.element += element_offset;
    be.body += body_offset;
    boundary_edges.push_back(be);
  }
  for (const auto& [name, ids] : other.node_groups) {
    auto& dst = node_groups[prefix + name];
    for (int id : ids) dst.push_back(id + node_offset);
  }
  for (const auto& [name, ids] : other.edge_groups) {
    auto& dst = edge_groups[prefix + name];
    for (int id : ids) dst.push_back(id + edge_offset);
  }
}

std::pair<double, int> Mesh::angle_quality(double skinny_deg) const {
  double smallest = 180.0;
  int skinny = 0;
  for (const auto& e : elements) {
    double tri_min = 180.0;
    for (int k = 0; k < 3; ++k) {
      const Vec2 a = nodes[e[(k + 1) % 3]] - nodes[e[k]], b = nodes[e[(k + 2) % 3]] - nodes[e[k]];
      const double angle = angle_between(a, b);
      tri_min = std::min(tri_min, angle * 180.0 / M_PI);
    }
    smallest = std::min(smallest, tri_min);
    skinny += tri_min < skinny_deg;
  }
  return {smallest, skinny};
}

std::pair<double, double> Mesh::edge_length_range() const {
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  for (const auto& el : elements)
    for (int k = 0; k < 3; ++k) {
      const double l = (nodes[el[k]] - nodes[el[(k + 1) % 3]]).norm();
      lo = std::min(lo, l);
      hi = std::max(hi, l);
    }
  return {lo, hi};
}

Eigen::Vector4d Mesh::bounding_box() const {
  Eigen::Vector4d box(std::numeric_limits<double>::infinity(),
                      std::numeric_limits<double>::infinity(),
                      -std::numeric_limits<double>::infinity(),
                      -std::numeric_limits<double>::infinity());
  for (const auto& p : nodes) {
    box[0] = std::min(box[0], p.x());
    box[1] = std::min(box[1], p.y());
    box[2] = std::max(box[2], p.x());
    box[3] = std::max(box[3], p.y());
  }
  return box;
}

// ---------------------------------------------------------------------------------------------

PointLocator::PointLocator(const Mesh& mesh) : mesh_(mesh) {
  box_ = mesh.bounding_box();
  const double w = std::max(box_[2] - box_[0], 1e-300), h = std::max(box_[3] - box_[1], 1e-300);
  const double cells = std::max(1.0, static_cast<double>(mesh.num_elements()));
  const double side = std::sqrt(w * h / cells);
  nx_ = std::clamp(static_cast<int>(w / side) + 1, 1, 4096);
  ny_ = std::clamp(static_cast<int>(h / side) + 1, 1, 4096);
  hx_ = w / nx_;
  hy_ = h / ny_;
  cells_.assign(static_cast<size_t>(nx_) * ny_, {});
  node_cells_.assign(static_cast<size_t>(nx_) * ny_, {});
  for (int e = 0; e < mesh.num_elements(); ++e) {
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    for (int i = 0; i < mesh.nodes_per_element(); ++i) {
      const Vec2& p = mesh.nodes[mesh.elements[e][i]];
      x0 = std::min(x0, p.x());
      y0 = std::min(y0, p.y());
      x1 = std::max(x1, p.x());
      y1 = std::max(y1, p.y());
    }
    const int i0 = std::clamp(static_cast<int>((x0 - box_[0]) / hx_), 0, nx_ - 1);
    const int i1 = std::clamp(static_cast<int>((x1 - box_[0]) / hx_), 0, nx_ - 1);
    const int j0 = std::clamp(static_cast<int>((y0 - box_[1]) / hy_), 0, ny_ - 1);
    const int j1 = std::clamp(static_cast<int>((y1 - box_[1]) / hy_), 0, ny_ - 1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) cells_[static_cast<size_t>(j) * nx_ + i].push_back(e);
  }
  for (int n = 0; n < mesh.num_nodes(); ++n)
    node_cells_[cell_of(mesh.nodes[n].x(), mesh.nodes[n].y())].push_back(n);
}

int PointLocator::cell_of(double x, double y) const {
  const int i = std::clamp(static_cast<int>((x - box_[0]) / hx_), 0, nx_ - 1);
  const int j = std::clamp(static_cast<int>((y - box_[1]) / hy_), 0, ny_ - 1);
  return j * nx_ + i;
}

namespace {

// Inverts the isoparametric map of element e by Newton's method, starting from the
// straight-sided (corner) solution.
template <int NN>
bool invert_map(const Mesh& mesh, int e, const Vec2& p, double& a, double& b) {
  using Tri = Triangle<NN>;
  typename Tri::Coords x;
  for (int i = 0; i < NN; ++i) x.row(i) = mesh.nodes[mesh.elements[e][i]].transpose();
  for (int it = 0; it < 20; ++it) {
    const Vec2 r = (Tri::shape(a, b).transpose() * x).transpose() - p;
    const Eigen::Matrix2d jac = (Tri::shape_grad_ref(a, b).transpose() * x).transpose();
    const Vec2 d = jac.partialPivLu().solve(r);
    a -= d.x();
    b -= d.y();
    if (d.norm() < 1e-14) break;
  }
  return std::isfinite(a) && std::isfinite(b);
}

}  // namespace

PointLocator::Hit PointLocator::locate(const Vec2& p) const {
  const double tol = 1e-10;
  Hit best;
  double best_violation = 1e-6;  // accept points on or just outside an element boundary
  for (int e : cells_[cell_of(p.x(), p.y())]) {
    const auto& n = mesh_.elements[e];
    const Vec2 x0 = mesh_.nodes[n[0]];
    Eigen::Matrix2d m;
    m.col(0) = mesh_.nodes[n[1]] - x0;
    m.col(1) = mesh_.nodes[n[2]] - x0;
    Vec2 ab = m.partialPivLu().solve(p - x0);
    double a = ab.x(), b = ab.y();
    if (mesh_.order == 2) invert_map<6>(mesh_, e, p, a, b);
    const double violation = std::max({-a, -b, a + b - 1.0, 0.0});
    if (violation <= tol) return {e, a, b};
    if (violation < best_violation) {
      best_violation = violation;
      best = {e, std::clamp(a, 0.0, 1.0), std::clamp(b, 0.0, 1.0 - std::clamp(a, 0.0, 1.0))};
    }
  }
  return best;
}

int PointLocator::nearest_node(const Vec2& p) const {
  const int ci = std::clamp(static_cast<int>((p.x() - box_[0]) / hx_), 0, nx_ - 1);
  const int cj = std::clamp(static_cast<int>((p.y() - box_[1]) / hy_), 0, ny_ - 1);
  int best = -1;
  double best_d2 = std::numeric_limits<double>::infinity();
  // Grow rings of cells until the ring distance exceeds the best distance found.
  for (int ring = 0; ring <= std::max(nx_, ny_); ++ring) {
    for (int j = cj - ring; j <= cj + ring; ++j) {
      for (int i = ci - ring; i <= ci + ring; ++i) {
        if (i < 0 || j < 0 || i >= nx_ || j >= ny_) continue;
        if (std::max(std::abs(i - ci), std::abs(j - cj)) != ring) continue;
        for (int n : node_cells_[static_cast<size_t>(j) * nx_ + i]) {
          const double d2 = (mesh_.nodes[n] - p).squaredNorm();
          if (d2 < best_d2) {
            best_d2 = d2;
            best = n;
          }
        }
      }
    }
    const double reach = ring * std::min(hx_, hy_);
    if (best >= 0 && reach * reach >= best_d2) break;
  }
  return best;
}

}  // namespace c2d::core
