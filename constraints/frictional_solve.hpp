// FrictionalSolve, the set iteration behind FrictionalSolver (friction_solver.hpp): private to
// the constraints module. Its members are defined by responsibility in two files:
// friction_solver.cpp, which sets to solve (the starts, the method's rule on every row, the
// cycle handling and the dual active-set safeguard, the solution's fields), and
// frictional_systems.cpp, how one set is solved (the condensation onto the rows in play, or
// the whole saddle point by LU, and the work each path counts).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "constraints/constrained_problem.hpp"
#include "constraints/friction_solver.hpp"
#include "constraints/kkt_solver.hpp"
#include "constraints/set_rules.hpp"
#include "constraints/strategy_common.hpp"
#include "constraints/surface_condensation.hpp"
#include "constraints/row_memory.hpp"

namespace c2d::constraints {

// The sets, as the iteration tracks them: entry i (a gap row) is 1 when the row is held, entry
// m + i its tangential row's state (set_rules.hpp's Tangential), entry 2m + i the piece of its
// friction law that bounds it. A Coulomb row's tangential row is free while its normal row is;
// a Tresca row's (a law whose bound is positive at zero normal force) is not tied to it (the
// classical Tresca problem bounds the friction on the whole candidate surface, which keeps it
// convex: tying it to contact made the bound switch on and off with the contact and the sets
// cycle).

class FrictionalSolve {
 public:
  FrictionalSolve(const ConstrainedProblem& p, const RowMemory& memory);

  void run(const FrictionalOptions& options, ConstraintSolution& s);

 private:
  /// Whether a set iteration that cycles or wanders is finished by the dual active-set
  /// safeguard: a frictionless problem (the safeguard's steps keep λ ≥ 0 and raise the dual
  /// objective, which a friction law's slip conditions do not fit; a penalised row's gap is
  /// shifted by λ̂/k).
  bool safeguarded() const { return o_->safeguard && !p_.has_friction(); }

  /// A set's solve failed with `st`: the status, and the message with what the sets say.
  void solve_failed(SolveStatus st, const std::vector<char>& code, ConstraintSolution& s) const;

  /// The sets of a frictionless problem: the gap rows of `set` held, every tangential row free.
  std::vector<char> normal_code(const std::vector<char>& set) const;

  /// The dual active-set method (strategy_common.hpp) from the sets `code`, each set solved on
  /// the same factor, among the rows in play (the others cannot enter: their gaps are not on
  /// the tail); then the last set solved on its own, so that the state is that set's solution,
  /// and the left-out rows checked on the whole displacement: where one closes, they come into
  /// play and the safeguard runs again on the condensation made with them. `s` gets the
  /// status, the history and the state; `code` the last set.
  void safeguard(int it, std::vector<char>& code, ConstraintSolution& s);

  /// The memory's closed rows, every frictional one (and every Tresca row) sticking, each on
  /// its law's piece at the warm start's normal force (or none).
  std::vector<char> cold_start() const;

  /// The code of row i's law piece at normal force `normal` (and the piece remembered).
  char piece_code(int i, double normal) const;

  /// Row i's law piece of code `piece` (one piece_code() returned).
  const FrictionBound& piece_of(int i, char piece) const;

  /// The cold start with the previous state's friction states, or a given solution's sets.
  std::vector<char> warm_start(const std::vector<char>& cold) const;

  bool frictional(int i) const { return p_.frictional(i); }
  /// The rows' slip at u (zero without tangential rows).
  VecX slip(const VecX& u) const;
  bool tresca(int i) const { return binds_open_[i] != 0; }
  double compliance(const VecX& k, int i) const { return penalised_ ? 1.0 / k[i] : 0.0; }

  /// What row i's tangential row holds under the sets `code`, as both solves pose it: sticking
  /// (where it has a tangential row to hold, or a penalty), slipping along σ with
  /// λ_t = σ (offset + slope λ) on its law's piece, or nothing (λ_t = 0).
  struct Tangential {
    bool stick = false, slip = false;
    double sigma = 1.0;
    FrictionBound bound;
  };
  Tangential tangential(const std::vector<char>& code, int i) const;

  /// Why the last solve failed: its own message, else the LU's report.
  const std::string& failure_message() const {
    return message_.empty() ? kkt_.report().message : message_;
  }

  /// Solves the system of the sets `code` into s.u, λ, λ_t, μ: condensed onto the rows when
  /// K (regularised) factorises, else (or when the rows' dense block is singular) by LU of the
  /// whole saddle point. On the condensed path s.u holds the tail's values only (all the rules
  /// read) until complete_displacement().
  SolveStatus solve(const std::vector<char>& code, ConstraintSolution& out);

  SolveStatus solve_lu(const std::vector<char>& code, ConstraintSolution& out);

  core::SpdSolveReport surface_report() const;

  /// The condensation of K onto the rows in play (equality, normal, tangential: row r = j,
  /// me + i, me + m + i), factorised on first use with R = the equality rows and the eight
  /// normal rows nearest to closing with their tangential rows, or every row when those leave
  /// a rigid mode. In play: every equality row, the gap rows the sets `code` hold or that are
  /// closed at the linearisation point, every Tresca row (bound while open), and a margin of
  /// the open rows nearest to closing (choose_play()); the others are free and stay out of the
  /// tail, whose dense factor costs the cube of its size (a contact zone of 155 rows among 253
  /// candidates: half the flops). bring_into_play() checks them on the whole displacement.
  bool surface_ready(const std::vector<char>& code);

 public:
  /// Takes `surface`, a condensation of this problem's K, for the condensed path, with this
  /// solver's rows appended to it; false (and nothing changed) when they cannot be, or when
  /// this solver already chose its path.
  bool share(const std::shared_ptr<SurfaceCondensation>& surface);

 private:
  /// Cᵀ over this solver's rows: equality j, normal me + i, tangential me + m + i.
  SpMat surface_rows() const;

  /// The sets' system on the rows, in forces w = s z: a held row's saddle-point equation
  /// −s c·u − s² cmp z = rhs is c·u + cmp w = −rhs/s; a slipping row's force follows its normal
  /// row's, w_t = σ(offset + slope w_n); a free row's is zero.
  SolveStatus solve_condensed(const std::vector<char>& code, ConstraintSolution& out);

  /// The whole u of the last condensed solve (the rules needed its tail only); a penalised
  /// solve's refined (refine()). Once per solve: refine's corrections are the condensation's
  /// last solves, so completing again would return a correction, not u (bring_into_play()
  /// completes a settled solve before run() does).
  void complete_displacement(ConstraintSolution& s);

  /// Row forces w (the condensation's row order) into out's multipliers and forces.
  void take_forces(const VecX& w, ConstraintSolution& out) const;

  /// A penalised solve's residual at (u, w), relative to the largest load or force: K u − f −
  /// Cᵀ w (into r_u) and, per held row, k (target − c·u) − w (into r_rows).
  double penalised_residual(const SpMat& ct, const VecX& u, const VecX& w, VecX& r_u,
                            VecX& r_rows) const;

  /// Iterative refinement of a penalised condensed solve on the same factor, up to three
  /// corrections while each divides the residual by ten and it exceeds 1e-12: a stiff penalty's
  /// small penetration w/k then carries its own relative precision, and the forces k·g that
  /// the run's Newton takes from the gaps agree with the solve's (k = 1e20 on two bars'
  /// supports: the reactions exact).
  void refine(ConstraintSolution& s);

  bool in_play(int i) const { return play_.empty() || play_[i]; }
  bool all_in_play() const;

  /// The condensation's work since it was last counted, added to `s`.
  void count_surface_work(ConstraintSolution& s);

  /// Counts the condensation's work and drops it: the next solve makes it again (with the
  /// rows in play then).
  void drop_surface(ConstraintSolution& s);

  /// The rows in play (see surface_ready()): those `code` holds, the closed and the Tresca rows,
  /// those within the memory's closing reach (how far the last load step's contact grew), and
  /// a margin of the open rows nearest to closing (an eighth as many as those, at least 8). Every row when that would leave out fewer than a quarter of them or 48 (a dense tail
  /// that small costs less than the second factorisation a row that closes outside would take),
  /// or when fewer than an eighth of them or 8 are closed: a contact that is only beginning
  /// grows out of any margin (on Cattaneo–Mindlin, from 1 row to 79), and a body it alone
  /// holds is singular on its first rows.
  void choose_play(const std::vector<char>& code);

  /// Settled sets on a condensation without some rows: their gaps on the whole displacement,
  /// and where the rule would hold one, those rows (and the open rows within a tenth of the
  /// largest closure of this solve) brought into play, held in `next`, for a condensation made
  /// again. False when every left-out row stays open.
  bool bring_into_play(ConstraintSolution& s, std::vector<char>& next);

  /// The method's rule: the next sets from the solution; returns the iteration's residual (the
  /// largest violation of the complementarity conditions, as a force).
  double update(const ConstraintSolution& sol, const VecX& g, const VecX& sl,
                std::vector<char>& next) const;

  IterationRecord record(int it, const std::vector<char>& code, const std::vector<char>& next,
                         const VecX& g, double residual) const;

  /// The solution's friction fields and active set from the last sets.
  void finish(const std::vector<char>& code, bool solved, ConstraintSolution& s) const;

  const ConstrainedProblem& p_;
  const RowMemory& memory_;  ///< where the sets start (cold_start, warm_start)
  const FrictionalOptions* o_ = nullptr;
  int n_, me_, m_;
  double s_;
  bool penalised_ = false;
  const SetRule* rule_ = nullptr;  ///< the rule in use (ssn's falls back on a cycle)
  PrimalDualRule primal_dual_;     ///< the rule of a caller that names none
  std::vector<char> binds_open_;  ///< per row: its law bounds it while open (Tresca)
  /// Per row: the pieces of its law seen so far (the sets name a piece by its number).
  mutable std::vector<std::vector<FrictionBound>> pieces_;
  std::vector<std::vector<std::pair<int, double>>> eq_rows_, gap_rows_, slip_rows_;
  VecX slip0_;  ///< the rows' slip at the start (zero without tangential rows)
  KktSolver kkt_;
  bool analysed_ = false;
  bool factored_ = false;                 ///< kkt_ holds the factor of factored_code_'s system
  std::vector<char> factored_code_;
  std::array<VecX, 3> factored_k_;        ///< and of these stiffnesses (penalised rows)
  /// The condensed path (null: LU only), its own or another caller's with these rows appended
  /// from first_row_ on (equality, normal, tangential).
  std::shared_ptr<SurfaceCondensation> surface_;
  int first_row_ = 0;
  bool surface_tried_ = false;
  /// Per gap row: in the condensation (empty: every row; see surface_ready()).
  std::vector<char> play_;
  int broadened_ = 0;                     ///< times bring_into_play() added rows
  /// Why the last solve failed where the LU's report does not say it (else empty).
  std::string message_;
  core::SpdSolveReport counted_;          ///< the condensation's work counted so far
  double dense_counted_ = 0.0;
  /// The last condensed solve's row states and row forces (refine() corrects them).
  SurfaceCondensation::RowStates last_states_;
  VecX last_w_;
  bool completed_ = false;                ///< s.u is the whole u of the last condensed solve
  bool surface_last_ = false;             ///< the last solve took the condensed path
  double surface_rcond_ = 1.0;            ///< its dense block's condition estimate
};

}  // namespace c2d::constraints
