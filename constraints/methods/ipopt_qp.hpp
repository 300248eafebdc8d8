// The pieces of the ipopt method (ipopt_strategy.cpp) that its friction (ipopt_friction.cpp)
// shares: the QP's rows as Ipopt sees them, one Ipopt solve, and the reading of its forces.
#pragma once

#include <Eigen/Dense>
#include <IpTNLP.hpp>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "constraints/constraint_strategy.hpp"
#include "constraints/friction_solver.hpp"
#include "constraints/surface_condensation.hpp"

namespace c2d::constraints::ipopt_detail {

/// A constraint row kept for Ipopt: normalised coefficients, bounds, and where it came from.
struct KeptRow {
  std::vector<std::pair<int, double>> terms;
  double lower = 0, upper = 0, norm = 1;
  bool equality = false;
  int source = 0;  ///< index into the problem's equality or gap rows
};

struct RowSet {
  std::vector<KeptRow> rows;
  int dropped_zero = 0, dropped_duplicate = 0;
  std::string inconsistent;  ///< non-empty: contradictory duplicate rows
};

/// Normalises the rows and drops zero rows and duplicates (the tightest copy of a gap row is
/// kept; duplicate equalities must agree).
RowSet prepare_rows(const ConstrainedProblem& p);

struct QpOutcome {
  SolveStatus status = SolveStatus::kFailed;
  std::string message;
  VecX x, lambda;  ///< [u; p] and Ipopt's multipliers of the rows
  int iterations = 0;
};

/// An Ipopt problem that starts at 0, keeps its solution (x and the constraints' multipliers)
/// and stops when the run is interrupted.
class QpTnlp : public Ipopt::TNLP {
 public:
  VecX x, lambda;
  /// Every problem starts at x = 0 (Ipopt pushes it inside the bounds).
  bool get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* x0, bool, Ipopt::Number*,
                          Ipopt::Number*, Ipopt::Index, bool, Ipopt::Number*) override;
  bool intermediate_callback(Ipopt::AlgorithmMode, Ipopt::Index, Ipopt::Number, Ipopt::Number,
                             Ipopt::Number, Ipopt::Number, Ipopt::Number, Ipopt::Number,
                             Ipopt::Number, Ipopt::Number, Ipopt::Index, const Ipopt::IpoptData*,
                             Ipopt::IpoptCalculatedQuantities*) override;
  void finalize_solution(Ipopt::SolverReturn, Ipopt::Index n, const Ipopt::Number* x,
                         const Ipopt::Number*, const Ipopt::Number*, Ipopt::Index m,
                         const Ipopt::Number*, const Ipopt::Number* lambda, Ipopt::Number,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override;
};

/// Ipopt on `qp` (exact Hessian and Jacobian, both constant), its return code as a status.
QpOutcome optimise(Ipopt::SmartPtr<QpTnlp> qp, const StrategyOptions& o, double tolerance);

/// Ipopt on the QP of `rows` over x = [u; p] with auxiliary costs `cost` (empty: none).
QpOutcome run_ipopt(const ConstrainedProblem& p, const RowSet& rows, const VecX& cost,
                    const StrategyOptions& o, double tolerance);

/// A QP with dense data: minimise ½ xᵀ H x + qᵀ x subject to A x = rhs, lower ≤ x ≤ upper.
struct DenseQp {
  Eigen::MatrixXd h, a;  ///< n × n; m × n
  VecX q, rhs, lower, upper;
};

/// The contact problem condensed onto its rows as Ipopt's dual QP (ipopt_dual.cpp): with K
/// factorised once (SurfaceCondensation), the rows' forces w are the unknowns, the gaps the
/// gradient, and the rigid motions that only the rows hold the multipliers of the equilibrium
/// equations the forces must satisfy. The frictionless rows, and with friction one tangential
/// row per frictional gap row whose force a Tresca bound limits: each Tresca problem of the
/// fixed point changes only the bounds, never the factor.
class SurfaceDual {
 public:
  /// Null when the rows do not condense (too many unknowns or rows for a dense block, K not
  /// definite with its regularising rows or indefinite along a motion they hold, or a row off
  /// the displacements); the work of a factorisation that was made is then counted in `work`.
  static std::unique_ptr<SurfaceDual> build(const ConstrainedProblem& p, const RowSet& base,
                                            bool friction, ConstraintSolution& work);
  ~SurfaceDual();
  SurfaceDual(const SurfaceDual&) = delete;
  SurfaceDual& operator=(const SurfaceDual&) = delete;

  /// Ipopt on the dual, to `tolerance`, with each frictional row's tangential force within
  /// ±bound (empty: none), unbounded where `stick` (a sticking row). s gets the interior
  /// point's u and forces.
  QpOutcome solve(const VecX& bound, const std::vector<char>& stick, const StrategyOptions& o,
                  double tolerance, ConstraintSolution& s);
  /// Frictionless: the rows the last solve holds, solved exactly on the same factor until
  /// `rule` confirms them (at most `max_solves`, and not past a repeated set). True with s the
  /// exact solution.
  bool settle(const SetRule& rule, int max_solves, ConstraintSolution& s);
  /// The rows of the last solve: active where the force exceeds the gap, and an active
  /// frictional row slipping where its slip exceeds its force's distance to the bound (the
  /// interior point's indicators, scaled).
  void classify(ConstraintSolution& s) const;
  /// The last exact solve's status (kSingular: the held rows leave a rigid motion free).
  SolveStatus solved() const { return solved_; }
  /// The factorisation's work and figures, and the dual's own dense work, into s (a caller
  /// that shares the condensation counts its own dense work).
  void report(ConstraintSolution& s) const;
  /// The condensation, for a crossover that solves on the same factor.
  const std::shared_ptr<SurfaceCondensation>& surface() const { return surface_; }

 private:
  SurfaceDual(const ConstrainedProblem& p, const RowSet& base);
  bool condense();
  void forces(const VecX& w, ConstraintSolution& s) const;

  const ConstrainedProblem& p_;
  const RowSet& base_;
  std::shared_ptr<SurfaceCondensation> surface_;
  double own_dense_ = 0.0;          ///< dense seconds of this dual's own work on surface_
  VecX b_;                          ///< per dual row: C u ≥ b (= b: equality, sticking)
  std::vector<char> equality_;      ///< per dual row
  std::vector<int> tangential_of_;  ///< per gap row: its tangential dual row, or −1
  std::vector<std::pair<int, double>> tangential_;  ///< (gap row, |T_i|) per tangential row
  std::vector<int> all_, reg_;      ///< every dual row; the regularising ones
  Eigen::MatrixXd s_jr_, m_plus_, null_;
  VecX y0_r_, scale_, row_norm_;
  double sigma_ = 1.0;
  DenseQp qp_;
  VecX last_x_, last_grad_;         ///< the last solve's scaled x and gradient
  std::vector<char> held_;
  SolveStatus solved_ = SolveStatus::kFailed;
};

/// ipopt on the frictionless problem condensed onto its rows: the dual QP on one factorisation
/// of K, its set then solved exactly on the same factor and confirmed by `rule`; first from a
/// loose interior point while `loose_first` (cleared when the exact solves do not confirm one).
/// False when the rows do not condense (s then holds only the work of a factorisation that was
/// made); otherwise s is complete with its status.
bool solve_condensed_dual(const ConstrainedProblem& p, const RowSet& rows, const StrategyOptions& o,
                          const SetRule& rule, bool& loose_first, ConstraintSolution& s);

/// Forces from Ipopt's multipliers (its Lagrangian is f + gᵀλ: a row exerts −λ / |row|): the
/// gap rows' λ ≥ 0, the equality rows' μ, and λ_t from the friction rows (`friction_sign` per
/// row: 0 none, ±1 a Tresca face, 2 a sticking equality).
void extract_forces(const ConstrainedProblem& p, const RowSet& rows,
                    const std::vector<int>& friction_sign, const QpOutcome& qp,
                    ConstraintSolution& s);

/// The rows of an interior-point solution that carry force (above 1e-6 of the largest) and
/// touch (gap within the penetration tolerance): the others' forces are the barrier's O(μ/gap).
std::vector<char> touching_rows(const ConstrainedProblem& p, const StrategyOptions& o,
                                const ConstraintSolution& s);

/// The active rows of an interior-point solution, and (with `check_rigid_motion`) whether the
/// rows that hold it leave a rigid motion free (then status singular).
void settle_active_set(const ConstrainedProblem& p, const StrategyOptions& o,
                       ConstraintSolution& s, bool check_rigid_motion = true);

/// Friction: the fixed point of Tresca problems (ipopt_friction.cpp), on the surface's dual
/// when `try_surface` and the rows condense (`on_surface`; K factorised once for every
/// problem) and on the whole KKT system otherwise, from the rows `memory` gives closed and its
/// forces. It ends as soon as a problem's sets pass the crossover (`solver`'s exact solve of
/// them; `exact`: s is then the exact solution). Fills s (its history, status and the surface's
/// work), the QP iterations, and the last bounds; returns the message.
std::string solve_tresca_fixed_point(const ConstrainedProblem& p, const RowMemory& memory,
                                     const StrategyOptions& o, const RowSet& base,
                                     FrictionalSolver& solver, bool try_surface,
                                     ConstraintSolution& s, int& total_iterations, VecX& bound,
                                     bool& exact, bool& on_surface);

/// After the fixed point: unless it ended exact, the active rows, each one's stick or slip
/// (slip where its force reached the bound, to 1e-6) and the crossover that solves those sets
/// exactly; then the check that the rows holding the solution (sticking ones along t too) leave
/// no rigid motion free. Returns whether s is the exact solution of its sets.
bool finish_friction(const ConstrainedProblem& p, const StrategyOptions& o, const VecX& bound,
                     bool exact, FrictionalSolver& solver, ConstraintSolution& s);

}  // namespace c2d::constraints::ipopt_detail
