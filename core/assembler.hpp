// Sparse assembly into a pattern computed once and refilled in place.
#pragma once

#include <functional>
#include <vector>

#include "core/dof_map.hpp"
#include "core/mesh.hpp"
#include "core/types.hpp"

namespace c2d::core {

/// Assembles element matrices into the free-free block K_ff of a mesh's stiffness. The sparsity
/// pattern and a scatter map (element entry -> position in K_ff's value array) are built once;
/// later assemblies only overwrite values, so K_ff keeps its pattern and a solver can reuse its
/// symbolic analysis. Entries coupling free and constrained DOFs become the "lift" vector
/// K_fc u_c, so that K_ff u_f = f_f - K_fc u_c.
class Assembler {
 public:
  Assembler(const Mesh& mesh, const DofMap& dofs);

  /// Element matrix callback: fills the local matrix of element e (2 * nodes_per_element square).
  using ElementMatrixFn = std::function<void(int e, LocalMatrix& ke)>;

  /// Refills K_ff; when u_constrained is given, also returns lift = K_fc u_c. Chunks of
  /// consecutive elements of one colour (no node shared between them) are assembled colour
  /// after colour, concurrently with more than one thread (set_threads): `element_matrix` must
  /// then be safe to call from several threads at once. The sums per entry run in colour order
  /// whatever the threads, so K_ff is the same to the last bit on one thread as on several.
  void assemble(const ElementMatrixFn& element_matrix, const VecX* u_full, VecX* lift);

  /// Threads for assemble() (OpenMP): 1 = serial (the default), 0 = as many as OpenMP offers
  /// from kMinParallelElements elements on (one below).
  void set_threads(int threads);
  /// Colours of element chunks: the first elements of chunks that share no node; a chunk is
  /// chunk_size() consecutive elements (fewer at the end).
  const std::vector<std::vector<int>>& colours() const { return colours_; }
  int chunk_size() const { return chunk_; }

  const SpMat& matrix() const { return k_ff_; }
  SpMat& matrix() { return k_ff_; }
  const Mesh& mesh() const { return mesh_; }
  const DofMap& dofs() const { return dofs_; }

  /// Global DOF indices of element e.
  void element_dofs(int e, std::array<int, kMaxElementDofs>& dofs) const;

 private:
  const Mesh& mesh_;
  const DofMap& dofs_;
  SpMat k_ff_;
  std::vector<int> scatter_;  ///< per element, ndofe^2 positions (-1: not in K_ff)
  std::vector<std::vector<int>> colours_;
  int chunk_ = 1;
  int threads_ = 1;

  /// Adds element e's matrix into K_ff (and its lift).
  void add_element(int e, const LocalMatrix& ke, const VecX* u_full, VecX* lift);
  /// K_ff's sparsity pattern from node adjacency, with zero values.
  void build_pattern();
  /// Per element, the positions of its local matrix's entries in K_ff's values.
  void build_scatter();
  /// Colours chunks of consecutive elements so that chunks of one colour share no node.
  void colour_chunks();
};

}  // namespace c2d::core
