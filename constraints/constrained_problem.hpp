// The problem every constraint backend solves, and what each one reports back.
//
//   minimise   ½ uᵀ K u − fᵀ u
//   subject to A u = b                 (equality rows: supports, symmetry, multipoint constraints)
//              g(u) = g0 + G u ≥ 0      (inequality rows: contact gaps, negative = penetration)
//
// Sign conventions (shared by all backends): the Lagrangian is
//   L = ½ uᵀ K u − fᵀ u − μᵀ (A u − b) − λᵀ (G u + g0),
// so K u − f = Aᵀ μ + Gᵀ λ at a solution; λ ≥ 0 is the compressive normal contact force of a row
// and μ the force a multipoint constraint exerts on the structure.
//
// What a method carries from one solve to the next (warm starts, the kept row stiffnesses) is
// not the problem: it is a RowMemory (row_memory.hpp), handed to the solve beside the problem.
#pragma once

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "constraints/friction_law.hpp"
#include "constraints/row_memory.hpp"
#include "core/fill_ordering.hpp"
#include "core/solver_status.hpp"
#include "core/spd_solver.hpp"
#include "core/types.hpp"

namespace c2d::core {
class TailAnalyses;  // core/tail_cholesky.hpp
}

namespace c2d::constraints {

struct ConstrainedProblem {
  SpMat stiffness;       ///< K: n x n, symmetric positive (semi-)definite, both triangles stored
  VecX load;             ///< f: n
  SpMat eq_jacobian;     ///< A: m_eq x n
  VecX eq_rhs;           ///< b: m_eq
  SpMat gap_jacobian;    ///< G: m x n
  VecX gap0;             ///< g0: m
  /// Per inequality row: a fixed penalty stiffness the input prescribes (the seed's gap
  /// elements), 0 where the strategy chooses. Empty = none prescribed.
  VecX gap_penalty;
  /// Per gap row: its share of the slave surface (a mortar row's ∫Φ ds·t, a node-based row's
  /// slave tributary length·t), so that its force over it is the pressure at its node; the
  /// friction laws' traction bounds and the default penalties' spread use it. Empty: unknown.
  VecX gap_area;
  /// Per gap row: its slave node's whole share of the slave surface (gap_area uncut by a mortar
  /// row's overlap with the master's ends), and the contact surface (pair) it belongs to, −1
  /// for none. See gap_local_stiffness.
  VecX gap_node_area;
  std::vector<int> gap_surface;
  /// Friction (all empty: frictionless; see constraints/friction_solver.hpp). Per gap row i,
  /// the tangential row T_i: the slave's displacement relative to the master along the tangent
  /// t (the normal turned clockwise), so s = slip0 + T u is the row's slip in the step (from the
  /// last converged state). The friction force λ_t opposes it: the structure receives −T_iᵀ λ_t,
  /// |λ_t| ≤ the bound of the row's friction law at its normal force λ_i, and a row that slips
  /// carries the bound in the direction of its slip.
  SpMat slip_jacobian;        ///< T: m x n
  VecX slip0;                 ///< m
  /// m: each row's friction law (null: a frictionless row), shared with the scene's pairs.
  std::vector<std::shared_ptr<const FrictionLaw>> friction_law;
  VecX tangent_penalty_ratio; ///< m: k_t / k of penalty-type methods
  /// Optional fill-reducing elimination order of the n unknowns (core/fill_ordering.hpp, from
  /// the mesh); null or another size: CHOLMOD orders the matrices itself.
  std::shared_ptr<const core::FillOrder> ordering;
  /// Symbolic analyses of the surface-last factor kept between this problem's solves and the
  /// next iterate's (null: each factor analyses its own).
  std::shared_ptr<core::TailAnalyses> analyses;
  /// Length against which relative penetration tolerances are measured (smallest contact edge).
  double length_scale = 1.0;
  /// Size of the model (bounding-box diagonal), for absolute tolerances.
  double model_size = 1.0;

  int num_unknowns() const { return static_cast<int>(load.size()); }
  int num_equalities() const { return static_cast<int>(eq_rhs.size()); }
  int num_gaps() const { return static_cast<int>(gap0.size()); }
  /// Whether gap row i has friction (a law).
  bool frictional(int i) const;
  /// The piece of frictional row i's bound at normal force λ (clamped at 0).
  FrictionBound friction_bound(int i, double normal_force) const;
  /// Frictional row i's bound at normal force λ (clamped at 0): the largest |λ_t| it allows.
  double friction_limit(int i, double normal_force) const;
  /// Whether frictional row i carries friction while open (a Tresca bound).
  bool friction_binds_open(int i) const;
  /// Whether some gap row has friction.
  bool has_friction() const;

  /// Local stiffness of each row: Σ_j a_ij² K_jj / Σ_j a_ij². For a contact row this is the
  /// assembled stiffness of the elements around the slave node (and its master nodes), the
  /// scale FEBio, Kratos and Tribol derive their default penalties from.
  VecX row_stiffness(const SpMat& rows) const;
  /// The gap rows' local stiffness spread over each contact surface: one stiffness per area κ
  /// (the largest of its rows' row_stiffness over their slave node's area) times each row's
  /// area, so that a uniform pressure meets a uniform penetration and a penalty reproduces it
  /// exactly (a row's own row_stiffness follows the mesh's topology node by node); rows without
  /// a surface or an area keep their row_stiffness.
  VecX surface_stiffness() const;
  /// The gap rows' local stiffness, the base of default penalties: the stiffness `memory`
  /// kept for each row when it has one, else surface_stiffness().
  VecX gap_local_stiffness(const RowMemory& memory) const;
};

/// The rows of `top` followed by those of `bottom` (same column count).
SpMat stack_rows(const SpMat& top, const SpMat& bottom);

/// Gap below which a row counts as touching: 1e-12 × the model size.
double touch_tolerance(const ConstrainedProblem& p);
/// max(0, −g): the deepest penetration of a gap vector (0 when empty).
double max_penetration(const VecX& gap);

/// One iteration of a backend: enough to draw a convergence history or an activation trace.
struct IterationRecord {
  int iteration = 0;
  int active = 0;             ///< active inequality rows after this iteration
  int entering = 0;           ///< rows that became active
  int leaving = 0;            ///< rows that became inactive
  double max_penetration = 0; ///< max(0, −g) over the rows
  double penalty = 0;         ///< largest penalty / augmentation stiffness in use (0: none)
  double residual = 0;        ///< backend-specific: KKT or complementarity residual
  int stick = 0, slip = 0;    ///< frictional rows: active rows that stick and that slip
};

/// The state of a frictional row: open (no normal force), stick, or slip.
enum class FrictionState : char { kOpen = 0, kStick = 1, kSlip = 2 };

struct ConstraintSolution {
  SolveStatus status = SolveStatus::kFailed;
  std::string method;
  std::string message;        ///< why it did not converge; notes otherwise
  VecX u;                     ///< n
  VecX gap;                   ///< m: g0 + G u
  VecX contact_force;         ///< m: λ ≥ 0
  VecX eq_multiplier;         ///< m_eq: μ
  VecX eq_residual;           ///< m_eq: A u − b where the caller measured it (else empty)
  VecX eq_penalty;            ///< m_eq: penalty stiffness per equality row (penalty-type methods)
  VecX penalty;               ///< m: penalty stiffness used per row (penalty-type methods)
  std::vector<char> active;   ///< m: 1 where the row carries force
  /// Friction (empty when the problem has none): per row the friction force λ_t (against the
  /// slip along t), the slip s = slip0 + T u, and the row's FrictionState.
  VecX tangent_force;
  VecX slip;
  std::vector<FrictionState> friction_state;
  int iterations = 0;
  int factorizations = 0;
  /// Time in the linear solver, summed over the solve: symbolic analyses, numeric
  /// factorisations, triangular solves (with their residual checks). The rest of `seconds` is
  /// the method's own work (assembling its systems, W and Schur matrices, active-set logic).
  double symbolic_seconds = 0, numeric_seconds = 0, solve_seconds = 0;
  int symbolic_analyses = 0;
  /// The last factorisation's (its ordering empty where the method did not say).
  core::FactorInfo factor;
  /// Conditioning of the last factorisation: CHOLMOD's pivot ratio (penalty-type methods) or the
  /// saddle point's reciprocal condition estimate (lagrange, ssn); NaN where the method has none.
  double pivot_ratio = std::numeric_limits<double>::quiet_NaN();
  double max_penetration = 0; ///< max(0, −g)
  double max_eq_violation = 0;///< max |A u − b|
  double seconds = 0;
  std::vector<IterationRecord> history;
  std::vector<double> penalty_history;  ///< adaptive_penalty: largest k after each raise
  /// Non-empty when the method cannot pose this problem at all, and why (ipopt: K_T is not
  /// positive definite with every row regularising, so its QP is not convex): a method with
  /// a fallback (ConstraintStrategy::fallback) hands it the iterate.
  std::string not_applicable;
};

}  // namespace c2d::constraints
