// Sparse symmetric positive definite solver: CHOLMOD (supernodal or simplicial, chosen by
// CHOLMOD), with Eigen's SimplicialLDLT as a fallback. Symbolic analysis is kept while the
// sparsity pattern holds.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/fill_ordering.hpp"
#include "core/solver_status.hpp"
#include "core/types.hpp"

namespace c2d::core {

/// What a factorisation was, as summary.json's solver section names it. The reports of the
/// solvers (SpdSolveReport, KktSolveReport) are one, and the contact methods' solutions carry
/// their last one's.
struct FactorInfo {
  std::string ordering;           ///< CHOLMOD's chosen ordering (amd, metis, nesdis, ...)
  bool supernodal = false;        ///< CHOLMOD's factor is supernodal
  double factor_nonzeros = 0;     ///< non-zeros of L (fill)
  /// Unknowns in the separator of a two-way split factorisation (SplitCholesky); 0: one
  /// factorisation of the whole matrix.
  int separator = 0;
};

struct SpdSolveReport : FactorInfo {
  SolveStatus status = SolveStatus::kFailed;
  std::string backend;            ///< "cholmod" or "eigen_ldlt"
  std::string message;            ///< why it failed, empty on success
  double relative_residual = 0;   ///< ||K x - b|| / ||b||
  double pivot_ratio = 0;         ///< min/max of the factor's diagonal (conditioning proxy)
  int symbolic_analyses = 0;      ///< how often the pattern was analysed
  int numeric_factorizations = 0;
  double symbolic_seconds = 0;    ///< fill-reducing ordering and symbolic analysis, summed
  double numeric_seconds = 0;     ///< numeric factorisations, summed
  double solve_seconds = 0;       ///< triangular solves and residual checks, summed
};

class SpdSolver {
 public:
  enum class Backend { kCholmod, kEigenLdlt };
  /// With `fallback`, a matrix CHOLMOD cannot factorise is retried with Eigen's LDLT, which
  /// names singular and indefinite matrices by their pivots; without it the failure returns at
  /// once (for callers that have a better plan B).
  explicit SpdSolver(Backend preferred = Backend::kCholmod, bool fallback = true);
  ~SpdSolver();
  SpdSolver(const SpdSolver&) = delete;
  SpdSolver& operator=(const SpdSolver&) = delete;

  /// Factorizes K (lower triangle used). K is referenced, not copied: it must stay alive and
  /// unchanged until the last solve() with this factorisation (the residual check reads it).
  /// Reuses the symbolic analysis if K's pattern is the one last analysed (compared in full).
  SolveStatus factorize(const SpMat& k);
  /// Solves K x = b with the last factorization; checks the residual and finiteness.
  SolveStatus solve(const VecX& b, VecX& x);
  /// Solves K X = B for several right-hand sides at once; checks finiteness and the largest
  /// relative column residual.
  SolveStatus solve(const Eigen::MatrixXd& b, Eigen::MatrixXd& x);
  const SpdSolveReport& report() const { return report_; }
  /// Eliminates in `fill`'s order (e.g. mesh_fill_order) instead of CHOLMOD's AMD, for
  /// matrices of its size (any other size: AMD); the report names it `name`. When `fill`
  /// carries a split, the two halves factorise separately, side by side when OpenMP offers two
  /// threads (SplitCholesky; a split that does not apply to the matrix: one factorisation).
  /// CHOLMOD's backend only; LDLT keeps its own AMD.
  void set_ordering(std::shared_ptr<const FillOrder> fill, std::string name);
  /// Forgets the symbolic analysis (call when the pattern changed).
  void reset_pattern();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  SpdSolveReport report_;
};

}  // namespace c2d::core
