// Sparse LU (UMFPACK through Eigen) for the indefinite saddle-point systems of the multiplier
// methods. The symbolic analysis is kept while the caller keeps the pattern fixed.
#pragma once

#include <memory>
#include <string>

#include "core/solver_status.hpp"
#include "core/spd_solver.hpp"
#include "core/types.hpp"

namespace c2d::constraints {

/// FactorInfo: the last factorisation's (SpdSolveReport's, "umfpack" for an LU).
struct KktSolveReport : core::FactorInfo {
  KktSolveReport() { ordering = "umfpack"; }
  SolveStatus status = SolveStatus::kFailed;
  std::string message;
  double relative_residual = 0.0;
  double rcond = 0.0;  ///< UMFPACK's reciprocal condition estimate (min/max |U_ii|)
  int symbolic_analyses = 0;
  int numeric_factorizations = 0;
  double symbolic_seconds = 0;  ///< summed over analyses (of every factor the solver keeps)
  double numeric_seconds = 0;   ///< summed over numeric factorisations
  double solve_seconds = 0;     ///< summed over solves, residual checks included
};

class KktSolver {
 public:
  KktSolver();
  ~KktSolver();
  KktSolver(const KktSolver&) = delete;
  KktSolver& operator=(const KktSolver&) = delete;

  /// Factorizes M; with `same_pattern` the previous symbolic analysis is reused.
  SolveStatus factorize(const SpMat& m, bool same_pattern);
  /// Solves M x = b; checks finiteness and the residual.
  SolveStatus solve(const VecX& b, VecX& x);
  const KktSolveReport& report() const { return report_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  KktSolveReport report_;
};

}  // namespace c2d::constraints
