// A stiffness condensed onto a set of constraint rows: the linear algebra of a constrained
// solve whose rows change state (held, slipping, free) while K stays.
//
//   K u = f + Cᵀ w,   C = the rows c_r (r = 0..rows−1), w their forces.
//
// K_ρ = K + Σ_{q∈R} ρ_q c_q c_qᵀ is factorised once, with every unknown a row touches ordered
// last (core::TailCholesky: L₂₂ is K_ρ condensed onto that tail). R is a set of regularising rows
// that makes a body held only by its constraints definite; the caller cancels them exactly with
// one auxiliary force ζ_q per q (c_q·u − ζ_q/ρ_q = 0), so u is that of K, not of K_ρ. Then, on
// the rows only, with v_r = L₂₂⁻¹ c_r and D₂ the tail's pivots:
//   S = C K_ρ⁻¹ Cᵀ,  S_rc = v_rᵀ D₂⁻¹ v_c    (columns computed when a row is first asked for)
//   y0 = C K_ρ⁻¹ f,   y0_r = v_rᵀ w₂          (w = (L D)⁻¹ P f, kept while f is)
//   u on the tail = L₂₂⁻ᵀ (w₂ + D₂⁻¹ V w)      (all the rows' values need)
// and the whole u with one back substitution. A change of the rows' states then costs dense
// work on the rows in play, never another sparse factorisation: the frictional surface block
// (non-symmetric through its slip rows) is a small dense LU.
//
// Bodies apart. K couples no two bodies; only the rows do (contact rows join slave and master).
// So R is first the caller's rows that must regularise (equalities) plus *anchor rows* of the
// condensation's own: the two displacements of two tail nodes of each connected part of K
// (a body, with what its equality rows tie to it), which remove its rigid motions without
// joining it to another. The tail is ordered part by part, and L₂₂ is block diagonal: its
// factorisation costs Σ k_b³ instead of (Σ k_b)³, each solve Σ k_b² (a cylinder on a block:
// about a quarter and a half). Where that leaves K_ρ singular (a part with a mechanism), R takes
// contact rows as before, which join the parts into one block. Anchor rows are never held;
// their forces are the auxiliary ζ alone, so they change nothing in the solution.
#pragma once

#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "core/fill_ordering.hpp"
#include "core/spd_solver.hpp"
#include "core/tail_cholesky.hpp"
#include "core/types.hpp"

namespace c2d::constraints {

/// K_ρ = K + Σ_{q∈rows} ρ_q c_q c_qᵀ for the columns c_q of `ct` (Cᵀ, n × rows), ρ_q the row's
/// local stiffness over |c_q|² (Σ c_j² K_jj / (Σ c_j²)²), so that ρ_q c_q c_qᵀ is as stiff as K
/// around it. `rho` gets ρ per column of ct (0 outside `rows`, and for a row without
/// coefficients or local stiffness).
SpMat regularised_stiffness(const SpMat& k, const SpMat& ct, const std::vector<int>& rows,
                            VecX& rho);

class SurfaceCondensation;

/// K condensed onto the rows of `ct` (n × rows) and factorised, with R = `always` and the rows
/// of the eight `groups` nearest to closing (a group: a normal row with its tangential row; its
/// gap in `gap`, the smallest nearest), or of every group when those leave a rigid mode (a body
/// held only by its constraints). Null when the rows do not fit a dense surface block or K_ρ is
/// not definite even with every group (then `*unfactorised`, if given, is set).
/// With `anchor` (see above), first R = `always` and anchor rows. Without it (a caller that reads
/// ρ and R itself: ipopt's dual), R never holds rows of the condensation's own.
std::unique_ptr<SurfaceCondensation> condense_onto_rows(
    SpMat ct, const SpMat& k, std::shared_ptr<const core::FillOrder> ordering,
    std::shared_ptr<core::TailAnalyses> analyses, const std::vector<int>& always,
    std::vector<std::vector<int>> groups, const std::vector<double>& gap, bool anchor = true,
    bool* unfactorised = nullptr);

class SurfaceCondensation {
 public:
  /// Largest tail (unknowns the rows touch) and number of rows the condensation takes: L₂₂ and
  /// S are dense.
  static constexpr int kMaxTail = 4000;
  static constexpr int kMaxRows = 2000;

  /// `ct`: Cᵀ, n × rows (each column one row's coefficients). The rows' pattern is kept.
  /// `analyses` (may be null): symbolic analyses shared with the other condensations of the run.
  SurfaceCondensation(SpMat ct, std::shared_ptr<const core::FillOrder> ordering,
                      std::shared_ptr<core::TailAnalyses> analyses = nullptr);
  ~SurfaceCondensation();
  SurfaceCondensation(const SurfaceCondensation&) = delete;
  SurfaceCondensation& operator=(const SurfaceCondensation&) = delete;

  /// Whether the rows fit the condensation at all (tail and row count within the limits).
  bool fits() const;
  /// Factorises K_ρ with R = `regularise` (row indices; ρ_q = the row's local stiffness over
  /// |c_q|², so that ρ_q c_q c_qᵀ is as stiff as K around it). False when K_ρ is not positive
  /// definite to working precision (pivot ratio 1e-11): R leaves a rigid mode, or K_σ made K
  /// indefinite. `k` is referenced until the next factorize.
  /// With `anchor`, R also holds anchor rows (rows() and beyond), two per tail node anchored.
  bool factorize(const SpMat& k, const std::vector<int>& regularise, bool anchor = false);
  /// The caller's rows (the columns of `ct`, and those add_rows() appended).
  int rows() const { return rows_; }
  /// Appends rows (the columns of `more`, n × k) to a factorised condensation, so that a second
  /// caller with rows of its own solves on the same factor (ipopt's crossover on its dual's):
  /// the first new row's index, or −1 when the condensation holds anchor rows, is not
  /// factorised, would exceed kMaxRows, or a new row touches an unknown outside the tail (the
  /// factor's tail is fixed). The new rows regularise nothing (ρ = 0).
  int add_rows(const SpMat& more);
  /// The diagonal blocks of L₂₂ (the tail's parts) of the last factorisation.
  int tail_blocks() const { return static_cast<int>(block_start_.size()) - 1; }
  /// ρ per row (0 outside R), anchor rows last.
  const VecX& rho() const { return rho_; }

  /// The rows' states for one solve, in terms of the row forces w (u = K⁻¹(f + Cᵀ w), K's
  /// solution, not K_ρ's; rows not listed carry no force):
  struct RowStates {
    /// Held rows: c_r·u + compliance_r w_r = target_r (compliance 0: an exact constraint).
    std::vector<int> held;
    std::vector<double> compliance, target;
    /// Following rows: w_r = offset_r + factor_r w_{leader_r} (leader_r a held row, or −1).
    std::vector<int> following, leader;
    std::vector<double> offset, factor;
    void hold(int r, double c, double t) { held.push_back(r), compliance.push_back(c), target.push_back(t); }
    void follow(int r, int lead, double off, double fac) {
      following.push_back(r), leader.push_back(lead), offset.push_back(off), factor.push_back(fac);
    }
  };
  /// Solves K u = f + Cᵀ w with the rows in `states`: a dense system on the held rows' forces
  /// and one auxiliary force ζ_q per regularising row (c_q·u − ζ_q/ρ_q = 0, which cancels
  /// ρ_q c_q c_qᵀ exactly), eliminated in closed form where the row is held. `force` gets
  /// every row's force, `u` the displacement on the tail (zero elsewhere; complete() gives the
  /// whole), `rcond` the dense block's condition estimate.
  /// kSingular when that block is singular (dependent rows, an unsupported body).
  SolveStatus solve(const VecX& f, const RowStates& states, VecX& force, VecX& u, double& rcond);
  /// The whole u of the last solve (one back substitution).
  SolveStatus complete(VecX& u);

  /// S[rows, cols] (dense).
  Eigen::MatrixXd schur(const std::vector<int>& rows, const std::vector<int>& cols);
  /// C K_ρ⁻¹ f for the rows `rows` (f's forward substitution kept while f is).
  SolveStatus rest_values(const VecX& f, const std::vector<int>& rows, VecX& y0);
  /// u = K_ρ⁻¹ (f + Σ_j w_j c_{cols_j}): on the tail only (zero elsewhere) with `tail_only`,
  /// which is all that the rows' values c_r·u need; else the whole u.
  SolveStatus displacement(const VecX& f, const std::vector<int>& cols, const VecX& w, VecX& u,
                           bool tail_only);

  /// K_ρ's factorisations, symbolic analyses and times (TailCholesky's), and the dense work.
  const core::SpdSolveReport& report() const { return tail_.report(); }
  double dense_seconds() const { return dense_seconds_; }
  /// The last solve's dense block residual, ‖a x − b‖ / ‖b‖.
  double relative_residual() const { return relative_residual_; }
  const std::string& message() const { return message_; }

 private:
  /// One entry of the map from the block's unknowns X (held rows' forces, auxiliary forces) to
  /// the row forces W_J: W_col += v X_x.
  struct BlockEntry {
    int col, x;
    double v;
  };
  /// Whether a regularising row's equation in the dense block `a` (held rows first, then those
  /// of `reg`) cancelled to round-off against its terms (S[eq, cols] through `b_map`, 1/ρ).
  bool cancels(const Eigen::MatrixXd& a, const Eigen::MatrixXd& s_ej,
               const std::vector<BlockEntry>& b_map, int nh, const std::vector<int>& reg) const;
  /// v_r for every row of `rows` (new ones in one dense triangular solve) and S's new columns.
  void prepare(const std::vector<int>& rows);
  SolveStatus forward(const VecX& f);
  /// block_start_ from the factor's tail.
  void find_blocks();
  /// ct_ = the caller's rows and, with `anchor`, the anchor rows of each part (tail_part_);
  /// returns R: `regularise` and the anchor rows' indices.
  std::vector<int> set_anchors(const std::vector<int>& regularise, bool anchor);

  SpMat user_ct_;                  ///< the caller's rows
  int rows_ = 0;
  SpMat ct_;                       ///< the caller's rows, then the anchor rows
  std::vector<int> tail_dofs_;     ///< the tail (ascending)
  std::vector<int> tail_part_;     ///< each one's part (the factor groups its tail by part)
  std::vector<int> block_start_;   ///< where each part starts in the factor's tail (and its end)
  core::TailCholesky tail_;
  SpMat k_rho_;                    ///< K_ρ, factorised in tail_
  VecX rho_;
  bool factored_ = false;
  std::vector<int> known_;         ///< rows whose v and S entries are computed, in order
  std::vector<int> slot_;          ///< per row: its place in known_, or −1
  Eigen::MatrixXd v_;              ///< kt × known_.size(): v_r per known row
  Eigen::MatrixXd s_;              ///< S over known_ × known_
  VecX cached_f_, forward_;        ///< the last f and its forward substitution
  std::vector<int> last_cols_;     ///< the last solve's rows with a force (with ζ folded in)
  VecX last_w_;                    ///< and those forces
  double dense_seconds_ = 0.0;
  double relative_residual_ = 0.0;
  std::string message_;
};

}  // namespace c2d::constraints
