// Element-size fields for error-driven remeshing (the optimal-mesh criterion of Zienkiewicz and
// Zhu, as in the seed's annex): new sizes from the ZZ local parameters, per body.
#pragma once

#include <array>
#include <vector>

#include "core/mesh.hpp"

namespace c2d::core {

/// Requested element sizes as nodal values on a triangulation of one body (reference
/// configuration), interpolated linearly inside each triangle. gmsh meshes the body again with
/// it as the background mesh.
struct SizeField {
  std::vector<std::array<Vec2, 3>> triangles;
  std::vector<std::array<double, 3>> sizes;

  bool empty() const { return triangles.empty(); }
  double min() const;
  double max() const;
};

struct SizeLimits {
  double max_shrink = 0.2;  ///< h_new >= max_shrink * h per cycle
  double max_growth = 2.0;  ///< h_new <= max_growth * h per cycle
};

/// Edge length of an element: the mean of its three corner-to-corner edges.
double element_size(const Mesh& mesh, int e);

/// One size field per body: h_new = h_e / ξ_e^(1/p) on every element (p the element order,
/// ξ_e the ZZ local parameter; ξ_e = 1 leaves h unchanged), bounded by `limits`, then
/// carried to the corner nodes as the smallest over the elements that share them.
std::vector<SizeField> optimal_size_fields(const Mesh& mesh, const std::vector<double>& local_parameter,
                                           int num_bodies, const SizeLimits& limits = {});

}  // namespace c2d::core
