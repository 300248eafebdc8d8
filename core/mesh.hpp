// Unstructured triangle mesh (T3 or T6) of one or more bodies.
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace c2d::core {

/// A boundary edge: 2 nodes (T3) or 3 nodes (T6: ends, then mid-side node), ordered so that the
/// owning element lies on the left (counter-clockwise traversal); the outward normal is
/// (t_y, -t_x) for tangent t.
struct BoundaryEdge {
  std::array<int, 3> nodes{-1, -1, -1};
  int element = -1;
  int body = -1;
};

class Mesh {
 public:
  int order = 1;                             ///< 1: T3, 2: T6
  std::vector<Vec2> nodes;                   ///< coordinates
  std::vector<std::array<int, 6>> elements;  ///< corner nodes first (CCW); T6 mid-sides 3, 4, 5
  std::vector<int> element_body;             ///< body index of each element
  std::vector<int> element_material;         ///< material index of each element
  std::vector<BoundaryEdge> boundary_edges;  ///< built by build_boundary()
  /// Named node sets (gmsh physical groups, legacy sets).
  std::map<std::string, std::vector<int>> node_groups;
  /// Named boundary edge sets: indices into boundary_edges.
  std::map<std::string, std::vector<int>> edge_groups;

  int nodes_per_element() const { return order == 1 ? 3 : 6; }
  int num_nodes() const { return static_cast<int>(nodes.size()); }
  int num_elements() const { return static_cast<int>(elements.size()); }
  int num_dofs() const { return 2 * num_nodes(); }

  /// Reorders every element counter-clockwise; returns how many were flipped.
  int orient_counter_clockwise();
  /// Finds the edges used by exactly one element.
  void build_boundary();
  /// Signed area of element e (corner nodes; exact for straight-sided T6).
  double corner_area(int e) const;
  /// Coordinates of element e as an NN x 2 matrix (NN = nodes per element).
  Eigen::MatrixX2d element_coords(int e) const;
  /// Appends another mesh (same order) with its bodies renumbered after this mesh's.
  void append(const Mesh& other, int body_offset, int material_offset, const std::string& prefix);
  /// Smallest and largest corner-to-corner edge length.
  std::pair<double, double> edge_length_range() const;
  /// Shape quality: the smallest interior angle (degrees) over the triangles' corners, and how
  /// many triangles have an angle below `skinny_deg` (skinny: poor conditioning and accuracy).
  std::pair<double, int> angle_quality(double skinny_deg = 15.0) const;
  /// Bounding box [xmin, ymin, xmax, ymax].
  Eigen::Vector4d bounding_box() const;
};

/// Finds the element that contains a point, through a uniform bucket grid over element bounding
/// boxes (O(1) per query on graded meshes of moderate grading).
class PointLocator {
 public:
  explicit PointLocator(const Mesh& mesh);
  struct Hit {
    int element = -1;
    double a = 0.0, b = 0.0;  ///< reference coordinates inside the element
  };
  /// Returns element -1 when the point lies outside every element (beyond a small tolerance).
  Hit locate(const Vec2& p) const;
  /// Nearest node to a point (exact, through the same grid).
  int nearest_node(const Vec2& p) const;

 private:
  const Mesh& mesh_;
  Eigen::Vector4d box_;
  int nx_ = 1, ny_ = 1;
  double hx_ = 1.0, hy_ = 1.0;
  std::vector<std::vector<int>> cells_;       ///< element ids per cell
  std::vector<std::vector<int>> node_cells_;  ///< node ids per cell
  int cell_of(double x, double y) const;
};

}  // namespace c2d::core
