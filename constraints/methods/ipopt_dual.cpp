// ipopt on the contact problem condensed onto its rows: the dual QP of the surface.
//
// With K condensed onto the rows C (surface_condensation.hpp: K_ρ = K + C_Rᵀ ρ C_R factorised
// once, S = C K_ρ⁻¹ Cᵀ, y0 = C K_ρ⁻¹ f), the row forces w (K u = f + Cᵀ w) and the regularising
// forces ζ (C_R u = ζ/ρ, which cancel ρ exactly) give the rows' values
//   C u = y0 + S_JJ w + S_JR ζ,    M ζ = y0_R + S_RJ w,    M = ρ⁻¹ − S_RR.
// With K positive semi-definite M is too, singular exactly on the rigid motions the rows R hold
// (D S_RR D, D = √ρ, has eigenvalue 1 there). With M⁺ its pseudo-inverse on the rest and
// N = D V₀ its null space,
//   ζ = M⁺ (y0_R + S_RJ w) + N α,   C u − b = H w + q + E α,
//   H = S_JJ + S_JR M⁺ S_RJ,  q = y0_J + S_JR M⁺ y0_R − b,  E = S_JR N,
// and solvability asks Nᵀ(y0_R + S_RJ w) = 0: the rows' forces balance the load on every rigid
// motion. That is the KKT system of the dual QP
//   minimise ½ wᵀ H w + qᵀ w   subject to  Eᵀ w = −Nᵀ y0_R,  w_gap ≥ 0,  |w_t| ≤ bound,
// whose gradient is the rows' values (gaps and slips) and whose equality multipliers are the
// rigid motions α. Ipopt solves it on the surface's dense block; the sparse K_ρ is factorised
// once for every problem of a solve (a Tresca fixed point changes only the bounds). Where K_T is
// indefinite along a motion the rows hold (compressive stresses under geometric nonlinearity),
// the dual holds that motion as if rigid, the nearest convex problem. The sets Ipopt finds are then
// solved exactly with K (a crossover, confirmed by the method's rule): the dual proposes, the
// exact solves decide, and a set they do not confirm sends the problem to the primal QP on the
// whole KKT system (ipopt_strategy.cpp).
#include <IpIpoptApplication.hpp>
#include <IpTNLP.hpp>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "constraints/active_set_tracker.hpp"
#include "constraints/methods/ipopt_qp.hpp"
#include "constraints/strategy_common.hpp"
#include "constraints/surface_condensation.hpp"

namespace c2d::constraints::ipopt_detail {

namespace {

using Ipopt::Index;
using Ipopt::Number;

/// A x and Aᵀ x that are zero, not a BLAS call, when A has no rows or no columns: with
/// EIGEN_USE_BLAS, Eigen hands dgemv a leading dimension of 0 for an empty A, and BLAS prints
/// "On entry to DGEMV parameter number 6 had an illegal value" on the user's stderr (a body
/// without rigid motions, or a dual without equations, has such blocks).
VecX times(const Eigen::MatrixXd& a, const VecX& x) {
  return a.size() == 0 ? VecX(VecX::Zero(a.rows())) : VecX(a * x);
}
VecX transpose_times(const Eigen::MatrixXd& a, const VecX& x) {
  return a.size() == 0 ? VecX(VecX::Zero(a.cols())) : VecX(a.transpose() * x);
}

/// 1 − (eigenvalue of D S_RR D) below this: a rigid motion of the rows R (the eigenvalue is 1
/// there to round-off of K_ρ's solves, whose pivot ratio the condensation keeps above 1e-11).
constexpr double kRigidGap = 1e-9;

/// Ipopt's tolerance on the frictionless dual (scaled: |q| ≤ 1, unit diagonal) for a first,
/// loose proposal of the set, and the exact solves that may confirm it.
constexpr double kSetProposalTolerance = 1e-4;
constexpr int kProposalSettleSolves = 4;

class DenseQpTnlp : public QpTnlp {
 public:
  explicit DenseQpTnlp(const DenseQp& d) : d_(d) {}

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac, Index& nnz_h,
                    IndexStyleEnum& style) override {
    n = static_cast<Index>(d_.q.size());
    m = static_cast<Index>(d_.rhs.size());
    nnz_jac = n * m;
    nnz_h = n * (n + 1) / 2;
    style = C_STYLE;
    return true;
  }
  bool get_bounds_info(Index n, Number* xl, Number* xu, Index m, Number* gl,
                       Number* gu) override {
    for (Index i = 0; i < n; ++i) xl[i] = d_.lower[i], xu[i] = d_.upper[i];
    for (Index r = 0; r < m; ++r) gl[r] = gu[r] = d_.rhs[r];
    return true;
  }
  bool eval_f(Index n, const Number* xp, bool, Number& obj) override {
    const Eigen::Map<const VecX> x(xp, n);
    obj = 0.5 * x.dot(d_.h * x) + d_.q.dot(x);
    return std::isfinite(obj);
  }
  bool eval_grad_f(Index n, const Number* xp, bool, Number* grad) override {
    const Eigen::Map<const VecX> x(xp, n);
    Eigen::Map<VecX>(grad, n) = d_.h * x + d_.q;
    return true;
  }
  bool eval_g(Index n, const Number* xp, bool, Index m, Number* g) override {
    if (m > 0) Eigen::Map<VecX>(g, m) = d_.a * Eigen::Map<const VecX>(xp, n);
    return true;
  }
  bool eval_jac_g(Index n, const Number*, bool, Index m, Index, Index* irow, Index* jcol,
                  Number* values) override {
    Index k = 0;
    for (Index r = 0; r < m; ++r)
      for (Index c = 0; c < n; ++c, ++k) {
        if (values) values[k] = d_.a(r, c);
        else irow[k] = r, jcol[k] = c;
      }
    return true;
  }
  bool eval_h(Index n, const Number*, bool, Number obj_factor, Index, const Number*, bool, Index,
              Index* irow, Index* jcol, Number* values) override {
    Index k = 0;
    for (Index r = 0; r < n; ++r)
      for (Index c = 0; c <= r; ++c, ++k) {
        if (values) values[k] = obj_factor * d_.h(r, c);
        else irow[k] = r, jcol[k] = c;
      }
    return true;
  }

 private:
  const DenseQp& d_;
};

/// Adds the dense work done on `surface` while it lives to `total` (on every way out): the
/// dual's own share of a condensation a crossover also solves on.
struct DenseWork {
  const SurfaceCondensation& surface;
  double& total;
  const double start = surface.dense_seconds();
  ~DenseWork() { total += surface.dense_seconds() - start; }
};

/// The exact solve of the rows `held` (dual-row indices; the equality rows always) on the
/// condensation: forces per dual row, u on the tail.
SolveStatus solve_held(SurfaceCondensation& surface, const VecX& f, const std::vector<char>& held,
                       const std::vector<char>& equality, const VecX& b, VecX& force,
                       VecX& u_tail) {
  SurfaceCondensation::RowStates states;
  for (int r = 0; r < static_cast<int>(held.size()); ++r)
    if (equality[r] || held[r]) states.hold(r, 0.0, b[r]);
  double rcond = 1.0;
  return surface.solve(f, states, force, u_tail, rcond);
}

}  // namespace

std::unique_ptr<SurfaceDual> SurfaceDual::build(const ConstrainedProblem& p, const RowSet& base,
                                                bool friction, ConstraintSolution& work) {
  auto d = std::unique_ptr<SurfaceDual>(new SurfaceDual(p, base));
  const int n = p.num_unknowns(), nb = static_cast<int>(base.rows.size());
  std::vector<Triplet> t;
  std::vector<double> b;
  for (int r = 0; r < nb; ++r) {
    for (const auto& [c, a] : base.rows[r].terms) {
      if (c >= n) return nullptr;
      t.emplace_back(c, r, a);
    }
    b.push_back(base.rows[r].lower);
    d->equality_.push_back(base.rows[r].equality);
  }
  // With friction, one tangential row per frictional gap row: c = T_i / |T_i|, its value less
  // b = −s0_i / |T_i| the slip over |T_i|, its force w = −|T_i| λ_t.
  d->tangential_of_.assign(p.num_gaps(), -1);
  const SpMat tt = p.slip_jacobian.transpose();
  for (int i = 0; i < p.num_gaps() && friction; ++i) {
    if (!p.frictional(i) || tt.col(i).nonZeros() == 0) continue;
    const double norm = tt.col(i).norm();
    if (!(norm > 0)) continue;
    const int r = static_cast<int>(b.size());
    for (SpMat::InnerIterator it(tt, i); it; ++it) t.emplace_back(it.row(), r, it.value() / norm);
    b.push_back(-p.slip0[i] / norm);
    d->equality_.push_back(0);
    d->tangential_of_[i] = r;
    d->tangential_.push_back({i, norm});
  }
  const int nj = static_cast<int>(b.size());
  if (nj == 0) return nullptr;
  d->b_ = Eigen::Map<const VecX>(b.data(), nj);
  SpMat ct(n, nj);
  ct.setFromTriplets(t.begin(), t.end());
  // Regularising rows: the equality rows, and the normal rows nearest to closing with their
  // tangential rows.
  std::vector<int> always;
  std::vector<std::vector<int>> groups;
  std::vector<double> gap;  // each group's −b: its gap over |G|
  for (int r = 0; r < nb; ++r) {
    if (base.rows[r].equality) {
      always.push_back(r);
      continue;
    }
    groups.push_back({r});
    if (const int tr = d->tangential_of_[base.rows[r].source]; tr >= 0) groups.back().push_back(tr);
    gap.push_back(-d->b_[r]);
  }
  // (no anchor rows: the dual reads R from ρ and treats its rows as the caller's)
  bool unfactorised = false;
  d->surface_ = condense_onto_rows(std::move(ct), p.stiffness, p.ordering, p.analyses, always,
                                   std::move(groups), gap, false, &unfactorised);
  if (unfactorised)
    work.not_applicable =
        "K_T is not positive definite with every contact row regularising (a motion only the "
        "rows' curvature holds, or none): Ipopt's QP is not strictly convex";
  if (!d->surface_) return nullptr;
  if (!d->condense()) {
    d->report(work);
    return nullptr;
  }
  return d;
}

SurfaceDual::SurfaceDual(const ConstrainedProblem& p, const RowSet& base) : p_(p), base_(base) {}
SurfaceDual::~SurfaceDual() = default;

bool SurfaceDual::condense() {
  SurfaceCondensation& surface = *surface_;
  const DenseWork work{surface, own_dense_};
  const int nj = static_cast<int>(b_.size());
  all_.resize(nj);
  std::iota(all_.begin(), all_.end(), 0);
  for (int r = 0; r < nj; ++r)
    if (surface.rho()[r] > 0) reg_.push_back(r);
  const Eigen::MatrixXd s = surface.schur(all_, all_);
  VecX y0;
  if (surface.rest_values(p_.load, all_, y0) != SolveStatus::kConverged || !s.allFinite())
    return false;
  const int nr = static_cast<int>(reg_.size());
  s_jr_.resize(nj, nr);
  Eigen::MatrixXd s_rr(nr, nr);
  y0_r_.resize(nr);
  VecX d(nr);
  for (int a = 0; a < nr; ++a) {
    d[a] = std::sqrt(surface.rho()[reg_[a]]);
    y0_r_[a] = y0[reg_[a]];
    s_jr_.col(a) = s.col(reg_[a]);
    for (int c = 0; c < nr; ++c) s_rr(a, c) = s(reg_[a], reg_[c]);
  }
  // M = ρ⁻¹ − S_RR = D⁻¹ (I − D S_RR D) D⁻¹: its pseudo-inverse and null space (the rigid
  // motions the regularising rows hold) from the eigenpairs of D S_RR D.
  Eigen::MatrixXd bmat = d.asDiagonal() * s_rr * d.asDiagonal();
  bmat = 0.5 * (bmat + bmat.transpose()).eval();
  if (!bmat.allFinite()) return false;
  Eigen::VectorXd values = Eigen::VectorXd::Zero(nr);
  Eigen::MatrixXd vectors = Eigen::MatrixXd::Identity(nr, nr);
  if (nr > 0) {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(bmat);
    if (eig.info() != Eigen::Success) return false;
    values = eig.eigenvalues(), vectors = eig.eigenvectors();
  }
  m_plus_ = Eigen::MatrixXd::Zero(nr, nr);
  std::vector<int> rigid;
  for (int k = 0; k < nr; ++k) {
    const double gap = 1.0 - values[k];
    const VecX dv = d.cwiseProduct(vectors.col(k));
    // A gap below 1 (M ≥ 0) is eliminated. At 0 the rows hold a rigid motion. Beyond 1 (a
    // negative gap) K_T is indefinite along a motion they hold (compressive stresses give a
    // body's rotation a small negative stiffness), where eliminating would make the dual
    // non-convex (1/gap < 0 in its Hessian): the dual takes it as a rigid motion too, so its
    // set is that of the nearest convex problem. The dual only proposes the set; the exact
    // solves with K_T decide (the crossover), and a set they do not confirm goes to the
    // primal on the whole system. (Iterating the dropped term, gap·α, on the equations'
    // right-hand side changed no set on any case measured, at up to 8 Ipopt solves a call.)
    if (gap > kRigidGap) m_plus_ += dv * dv.transpose() / gap;
    else rigid.push_back(k);
  }
  const int nz = static_cast<int>(rigid.size());
  null_.resize(nr, nz);
  for (int k = 0; k < nz; ++k) null_.col(k) = d.cwiseProduct(vectors.col(rigid[k]));
  const Eigen::MatrixXd sm = s_jr_ * m_plus_;
  Eigen::MatrixXd h = s + sm * s_jr_.transpose();
  h = 0.5 * (h + h.transpose()).eval();
  const VecX q = y0 + times(sm, y0_r_) - b_;
  const Eigen::MatrixXd e = s_jr_ * null_;          // nj × nz
  const VecX e_rhs = -transpose_times(null_, y0_r_);  // Eᵀ w = e_rhs
  // Scaled: w = σ T x, T = diag(1/√H_rr), the objective over σ², each rigid motion's equation
  // over its row norm. σ is the scale of what closes: the largest |q_r| T_r of the rows the rest
  // values close (q < 0), of the free-signed and the tangential rows, and each rigid motion's
  // balance |rhs| / |T e_k|; at most the largest |q_r| T_r of all rows. Taken over all rows, a
  // far open row set it (a ring's top, 2 above the floor under its own weight: σ 17.4 where the
  // contact's scale is 3.6e-3), the contact's forces and gaps lay 1e-5 below it, under Ipopt's
  // tolerance, and the interior point stopped with every row's force below its gap: an empty
  // set, then Ipopt on the whole system, 9 cutbacks and a failure after 305 s. σ scales the
  // problem only, not its solution.
  VecX t(nj);
  for (int r = 0; r < nj; ++r) t[r] = h(r, r) > 0 ? 1.0 / std::sqrt(h(r, r)) : 1.0;
  sigma_ = std::max(t.cwiseProduct(q).lpNorm<Eigen::Infinity>(), 1e-300);
  double closing = 0.0;
  for (int r = 0; r < nj; ++r)
    if (equality_[r] || r >= static_cast<int>(base_.rows.size()) || q[r] < 0)
      closing = std::max(closing, std::abs(t[r] * q[r]));
  for (int k = 0; k < nz; ++k)
    if (const double norm = t.cwiseProduct(e.col(k)).norm(); norm > 0)
      closing = std::max(closing, std::abs(e_rhs[k]) / norm);
  if (closing > 0) sigma_ = std::min(sigma_, closing);
  scale_ = sigma_ * t;
  qp_.h = t.asDiagonal() * h * t.asDiagonal();
  qp_.q = t.cwiseProduct(q) / sigma_;
  qp_.a = (scale_.asDiagonal() * e).transpose();  // nz × nj
  row_norm_ = VecX::Ones(nz);
  for (int k = 0; k < nz; ++k) {
    const double norm = qp_.a.row(k).norm();
    if (norm > 0) qp_.a.row(k) /= norm, row_norm_[k] = norm;
  }
  qp_.rhs = e_rhs.cwiseQuotient(row_norm_);
  qp_.lower = VecX::Zero(nj), qp_.upper = VecX::Constant(nj, 2e19);
  for (int r = 0; r < nj; ++r)
    if (equality_[r]) qp_.lower[r] = -2e19;
  return qp_.h.allFinite() && qp_.q.allFinite() && qp_.a.allFinite() && qp_.rhs.allFinite();
}

QpOutcome SurfaceDual::solve(const VecX& bound, const std::vector<char>& stick,
                             const StrategyOptions& o, double tolerance, ConstraintSolution& s) {
  for (const auto& [i, norm] : tangential_) {
    const int r = tangential_of_[i];
    const double limit = i < static_cast<int>(stick.size()) && stick[i] ? 2e19
                         : bound.size() == p_.num_gaps()                ? bound[i] * norm / scale_[r]
                                                                        : 0.0;
    qp_.lower[r] = -limit, qp_.upper[r] = limit;
  }
  Ipopt::SmartPtr<DenseQpTnlp> tnlp = new DenseQpTnlp(qp_);
  const QpOutcome out = optimise(tnlp, o, tolerance);
  const int nj = static_cast<int>(b_.size()), nz = static_cast<int>(qp_.rhs.size());
  const bool have = out.x.size() == nj && out.lambda.size() == nz;
  // The motions' amplitudes α = σ² λ / |row| (Ipopt's multipliers of the scaled equations).
  const VecX alpha =
      have ? VecX(sigma_ * sigma_ * out.lambda.cwiseQuotient(row_norm_)) : VecX(VecX::Zero(nz));
  const VecX w = have ? VecX(scale_.cwiseProduct(out.x)) : VecX(VecX::Zero(nj));
  // Held rows: where the scaled force exceeds the scaled gap, the gradient of the dual (an
  // interior point's active-set indicator: of two complementary quantities one tends to zero).
  held_.assign(nj, 0);
  last_x_ = VecX::Zero(nj), last_grad_ = VecX::Zero(nj);
  if (have) {
    last_x_ = out.x;
    last_grad_ = times(qp_.h, out.x) + qp_.q + transpose_times(qp_.a, out.lambda);
    for (int r = 0; r < nj; ++r) held_[r] = !equality_[r] && last_x_[r] > last_grad_[r];
  }
  // u of the interior point: ζ = M⁺ (y0_R + S_RJ w) + N α.
  const VecX zeta = times(m_plus_, y0_r_ + transpose_times(s_jr_, w)) + times(null_, alpha);
  std::vector<int> cols = all_;
  cols.insert(cols.end(), reg_.begin(), reg_.end());
  VecX weights(w.size() + zeta.size());
  weights << w, zeta;
  {
    const DenseWork work{*surface_, own_dense_};
    if (surface_->displacement(p_.load, cols, weights, s.u, false) != SolveStatus::kConverged)
      s.u = VecX::Zero(p_.num_unknowns());
  }
  forces(w, s);
  return out;
}

void SurfaceDual::forces(const VecX& w, ConstraintSolution& s) const {
  s.contact_force = VecX::Zero(p_.num_gaps());
  s.eq_multiplier = VecX::Zero(p_.num_equalities());
  if (p_.has_friction()) s.tangent_force = VecX::Zero(p_.num_gaps());
  for (size_t r = 0; r < base_.rows.size(); ++r) {
    const KeptRow& k = base_.rows[r];
    const double force = w[static_cast<int>(r)] / k.norm;
    if (k.equality) s.eq_multiplier[k.source] = force;
    else s.contact_force[k.source] = std::max(0.0, force);
  }
  for (const auto& [i, norm] : tangential_) s.tangent_force[i] = -w[tangential_of_[i]] / norm;
}

void SurfaceDual::classify(ConstraintSolution& s) const {
  s.active.assign(p_.num_gaps(), 0);
  s.friction_state.assign(p_.num_gaps(), FrictionState::kOpen);
  for (size_t r = 0; r < base_.rows.size(); ++r) {
    const int i = base_.rows[r].source;
    if (base_.rows[r].equality) continue;
    s.active[i] = held_[r];
  }
  for (const auto& [i, norm] : tangential_) {
    if (!s.active[i]) continue;
    const int r = tangential_of_[i];
    const double limit = qp_.upper[r], distance = limit - std::abs(last_x_[r]);
    const bool slips = limit < 1e18 && std::abs(last_grad_[r]) > distance;
    s.friction_state[i] = slips ? FrictionState::kSlip : FrictionState::kStick;
  }
}

bool SurfaceDual::settle(const SetRule& rule, int max_solves, ConstraintSolution& s) {
  // Each exact solve is dense work on the rows; the rule moves the rows an interior point
  // left on the wrong side (on a slender body, one or two per solve), until the set repeats.
  const int nj = static_cast<int>(b_.size());
  std::vector<char> held = held_;
  ActiveSetTracker sets;
  sets.record(held);
  VecX force, u_tail;
  const DenseWork work{*surface_, own_dense_};
  for (int k = 0; k < max_solves; ++k) {
    solved_ = solve_held(*surface_, p_.load, held, equality_, b_, force, u_tail);
    if (solved_ != SolveStatus::kConverged) return false;
    forces(force, s);
    s.active.assign(p_.num_gaps(), 0);
    for (size_t r = 0; r < base_.rows.size(); ++r)
      if (held[r]) {
        const int i = base_.rows[r].source;
        s.active[i] = 1;
        s.contact_force[i] = force[static_cast<int>(r)] / base_.rows[r].norm;
      }
    const VecX gap = p_.gap0 + p_.gap_jacobian * u_tail;  // the rows touch the tail only
    std::vector<char> next = s.active;
    next_normal_set(rule, p_, s.contact_force, gap, VecX(), VecX(), 1.0, next);
    IterationRecord rec;
    rec.iteration = s.iterations + k + 1;
    rec.max_penetration = max_penetration(gap);
    s.history.push_back(rec);
    std::vector<char> kept_next(nj, 0);
    for (size_t r = 0; r < base_.rows.size(); ++r)
      if (!base_.rows[r].equality) kept_next[r] = next[base_.rows[r].source];
    const ActiveSetTracker::Change change = sets.record(kept_next);
    if (change.unchanged) return surface_->complete(s.u) == SolveStatus::kConverged;
    if (change.repeated) return false;
    held = kept_next;
  }
  return false;
}

void SurfaceDual::report(ConstraintSolution& s) const {
  const core::SpdSolveReport none;
  add_solver_work(surface_->report(), none, s);
  s.solve_seconds += own_dense_;
  s.factor = surface_->report();
  s.pivot_ratio = surface_->report().pivot_ratio;
}

bool solve_condensed_dual(const ConstrainedProblem& p, const RowSet& rows, const StrategyOptions& o,
                          const SetRule& rule, bool& loose_first, ConstraintSolution& s) {
  const auto dual = SurfaceDual::build(p, rows, false, s);
  if (!dual) return false;
  // Frictionless, Ipopt only proposes the set and the exact solves decide (settle). On a
  // compact body an interior point's indicators (force against gap) separate the rows long
  // before its last digits (hertz_rigid_fast: 5 iterations at 1e-4 and 1 to 3 exact solves,
  // where 1e-10 takes 12), so the first proposal is a loose one, given a few exact solves.
  // Where they do not confirm it (a slender beam on a floor: 4 iterations, and 50 exact solves
  // did not settle), Ipopt again at the method's tolerance on the same factor, and the loose
  // proposals stop for the rest of the analysis (`loose_first`). A set neither confirms goes
  // to Ipopt on the whole system (the caller).
  const double loose = std::max(o.ipopt_tolerance, kSetProposalTolerance);
  const bool try_loose = loose_first && loose > o.ipopt_tolerance;
  int iterations = 0;
  for (const bool proposal : {true, false}) {
    if (proposal && !try_loose) continue;
    const QpOutcome out = dual->solve(VecX(), {}, o, proposal ? loose : o.ipopt_tolerance, s);
    iterations += out.iterations;
    s.iterations = iterations;
    s.status = out.status;
    s.message = out.message;
    if (out.status == SolveStatus::kConverged) {
      if (dual->settle(rule, proposal ? kProposalSettleSolves : o.max_iterations, s)) {
        s.message.clear();
      } else if (dual->solved() == SolveStatus::kSingular) {
        s.status = SolveStatus::kSingular;
        s.message =
            "the rows that hold Ipopt's solution leave the structure free to move (a "
            "body pulled off its supports, or unsupported)";
      } else {
        s.status = SolveStatus::kFailed;
        s.message = "the exact solves from Ipopt's contact set did not settle";
      }
    }
    if (s.status == SolveStatus::kConverged) break;
    if (proposal) loose_first = false;
  }
  if (s.history.empty()) s.history.emplace_back();
  dual->report(s);
  return true;
}

}  // namespace c2d::constraints::ipopt_detail
