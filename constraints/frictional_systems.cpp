// How FrictionalSolve solves the system of one set of row states (frictional_solve.hpp): on K
// condensed onto the rows in play (surface_condensation.hpp), or, where K does not factorise
// or the rows' dense block fails, the whole saddle point by UMFPACK; and the rows in play,
// chosen, checked and brought in.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "constraints/frictional_solve.hpp"

namespace c2d::constraints {

SolveStatus FrictionalSolve::solve(const std::vector<char>& code, ConstraintSolution& out) {
  SolveStatus condensed = SolveStatus::kFailed;
  std::string why;  // the condensed block's, when it failed
  if (surface_ready(code)) {
    condensed = solve_condensed(code, out);
    if (condensed == SolveStatus::kConverged) {
      surface_last_ = true;
      return SolveStatus::kConverged;
    }
    why = surface_->message();
    // A block singular with every row in play is the set's own singularity (a body its held
    // rows leave free, dependent rows): the whole saddle point of the same set is singular
    // too, and its LU would only cost a factorisation to say so.
    if (condensed == SolveStatus::kSingular && all_in_play()) {
      message_ = why;
      return SolveStatus::kSingular;
    }
    // The whole saddle point has every row in play, and so has a condensation made again.
    if (!all_in_play()) drop_surface(out);
  }
  surface_last_ = false;
  play_.assign(m_, 1);
  const SolveStatus st = solve_lu(code, out);
  // A set whose condensed block is singular and whose LU solve keeps no precision is
  // singular: the block says why (a free body, dependent rows).
  if (st == SolveStatus::kIllConditioned && condensed == SolveStatus::kSingular) {
    message_ = why;
    return SolveStatus::kSingular;
  }
  message_.clear();
  return st;
}

SolveStatus FrictionalSolve::solve_lu(const std::vector<char>& code, ConstraintSolution& out) {
  const int size = n_ + me_ + 2 * m_;
  const double s = s_;
  std::vector<Triplet> t;
  t.reserve(p_.stiffness.nonZeros() + 4 * (p_.eq_jacobian.nonZeros() +
                                           p_.gap_jacobian.nonZeros() +
                                           p_.slip_jacobian.nonZeros()) + 3 * (me_ + 2 * m_));
  for (int c = 0; c < p_.stiffness.outerSize(); ++c)
    for (SpMat::InnerIterator it(p_.stiffness, c); it; ++it) t.emplace_back(it.row(), c, it.value());
  VecX rhs = VecX::Zero(size);
  rhs.head(n_) = p_.load;
  // One row: its coefficients in both blocks (the row's own only when it holds c = 0).
  auto add_row = [&](int r, const std::vector<std::pair<int, double>>& coef, bool holds) {
    for (const auto& [j, a] : coef) {
      t.emplace_back(j, r, -s * a);
      t.emplace_back(r, j, holds ? -s * a : 0.0);
    }
  };
  for (int j = 0; j < me_; ++j) {
    const int r = n_ + j;
    add_row(r, eq_rows_[j], true);
    const double cmp = compliance(o_->k_eq, j);
    t.emplace_back(r, r, -s * s * cmp);
    rhs[r] = -s * p_.eq_rhs[j] - (penalised_ ? s * cmp * o_->mu_hat[j] : 0.0);
  }
  for (int i = 0; i < m_; ++i) {
    const int rn = n_ + me_ + i, rt = n_ + me_ + m_ + i;
    const bool on = code[i];
    add_row(rn, gap_rows_[i], on);
    const double cn = compliance(o_->k_gap, i);
    t.emplace_back(rn, rn, on ? -s * s * cn : s);
    rhs[rn] = on ? s * p_.gap0[i] - (penalised_ ? s * cn * o_->lambda_hat[i] : 0.0) : 0.0;
    // The tangential row: held when sticking, a slip condition when slipping, λ_t = 0
    // otherwise.
    const Tangential tr = tangential(code, i);
    add_row(rt, slip_rows_[i], tr.stick);
    const double ct = compliance(o_->k_tangent, i);
    t.emplace_back(rt, rt, tr.stick ? -s * s * ct : s);
    t.emplace_back(rt, rn, tr.slip ? -s * tr.bound.slope * tr.sigma : 0.0);
    if (tr.stick)
      rhs[rt] = -s * slip0_[i] - (penalised_ ? s * ct * o_->tangent_hat[i] : 0.0);
    else if (tr.slip)
      rhs[rt] = tr.sigma * tr.bound.offset;
  }
  // The matrix depends on the sets and the stiffnesses only: an augmented Lagrangian's next
  // multiplier update with the same sets needs a new right-hand side, not a new factor.
  const bool same = factored_ && code == factored_code_ && (!penalised_ ||
                    (o_->k_gap == factored_k_[0] && o_->k_tangent == factored_k_[1] &&
                     o_->k_eq == factored_k_[2]));
  SolveStatus st = SolveStatus::kConverged;
  if (!same) {
    SpMat a(size, size);
    a.setFromTriplets(t.begin(), t.end());
    st = kkt_.factorize(a, analysed_);
    analysed_ = true;
    factored_ = st == SolveStatus::kConverged;
    factored_code_ = code;
    if (penalised_) factored_k_ = {o_->k_gap, o_->k_tangent, o_->k_eq};
  }
  VecX x;
  if (st == SolveStatus::kConverged) st = kkt_.solve(rhs, x);
  if (st != SolveStatus::kConverged) return st;
  out.u = x.head(n_);
  out.eq_multiplier = s * x.segment(n_, me_);
  out.contact_force = s * x.segment(n_ + me_, m_);
  out.tangent_force = s * x.segment(n_ + me_ + m_, m_);
  return st;
}

FrictionalSolve::Tangential FrictionalSolve::tangential(const std::vector<char>& code,
                                                        int i) const {
  const char ts = code[m_ + i];
  Tangential t;
  t.stick = ts == kStick && (penalised_ || !slip_rows_[i].empty());
  t.slip = ts == kSlipPlus || ts == kSlipMinus;
  t.sigma = ts == kSlipMinus ? -1.0 : 1.0;
  if (t.slip && frictional(i)) t.bound = piece_of(i, code[2 * m_ + i]);
  return t;
}

core::SpdSolveReport FrictionalSolve::surface_report() const {
  return surface_ ? surface_->report() : core::SpdSolveReport{};
}

bool FrictionalSolve::surface_ready(const std::vector<char>& code) {
  if (surface_tried_) return surface_ != nullptr;
  surface_tried_ = true;
  if (play_.empty()) choose_play(code);
  SpMat ct = surface_rows();
  std::vector<int> eq(me_);
  for (int j = 0; j < me_; ++j) eq[j] = j;
  std::vector<std::vector<int>> groups(m_);
  for (int i = 0; i < m_; ++i) groups[i] = {me_ + i, me_ + m_ + i};
  surface_ = condense_onto_rows(std::move(ct), p_.stiffness, p_.ordering, p_.analyses, eq,
                                std::move(groups),
                                std::vector<double>(p_.gap0.begin(), p_.gap0.end()));
  first_row_ = 0;
  return surface_ != nullptr;
}

bool FrictionalSolve::share(const std::shared_ptr<SurfaceCondensation>& surface) {
  if (surface_tried_ || !surface) return false;
  const int first = surface->add_rows(surface_rows());
  if (first < 0) return false;
  surface_ = surface;
  first_row_ = first;
  surface_tried_ = true;
  play_.assign(m_, 1);
  return true;
}

SpMat FrictionalSolve::surface_rows() const {
  std::vector<Triplet> t;
  auto put = [&](int r, const std::vector<std::pair<int, double>>& coef) {
    for (const auto& [j, a] : coef) t.emplace_back(j, r, a);
  };
  for (int j = 0; j < me_; ++j) put(j, eq_rows_[j]);
  for (int i = 0; i < m_; ++i)
    if (in_play(i)) put(me_ + i, gap_rows_[i]), put(me_ + m_ + i, slip_rows_[i]);
  SpMat ct(n_, me_ + 2 * m_);
  ct.setFromTriplets(t.begin(), t.end());
  return ct;
}

SolveStatus FrictionalSolve::solve_condensed(const std::vector<char>& code, ConstraintSolution& out) {
  SurfaceCondensation::RowStates st;
  const int eq = first_row_, normal = first_row_ + me_, tangent = normal + m_;
  for (int j = 0; j < me_; ++j) {
    const double c = compliance(o_->k_eq, j);
    st.hold(eq + j, c, p_.eq_rhs[j] + (penalised_ ? c * o_->mu_hat[j] : 0.0));
  }
  for (int i = 0; i < m_; ++i) {
    if (code[i]) {
      const double c = compliance(o_->k_gap, i);
      st.hold(normal + i, c, -p_.gap0[i] + (penalised_ ? c * o_->lambda_hat[i] : 0.0));
    }
    const Tangential tr = tangential(code, i);
    if (tr.stick) {
      const double c = compliance(o_->k_tangent, i);
      st.hold(tangent + i, c, slip0_[i] + (penalised_ ? c * o_->tangent_hat[i] : 0.0));
    } else if (tr.slip) {
      st.follow(tangent + i, code[i] ? normal + i : -1, tr.sigma * tr.bound.offset,
                tr.sigma * tr.bound.slope);
    }
  }
  const SolveStatus status = surface_->solve(p_.load, st, last_w_, out.u, surface_rcond_);
  if (status != SolveStatus::kConverged) return status;
  completed_ = false;
  last_states_ = std::move(st);
  take_forces(last_w_, out);
  return status;
}

void FrictionalSolve::take_forces(const VecX& w, ConstraintSolution& out) const {
  out.eq_multiplier = w.segment(first_row_, me_);
  out.contact_force = w.segment(first_row_ + me_, m_);
  out.tangent_force = w.segment(first_row_ + me_ + m_, m_);
}

void FrictionalSolve::complete_displacement(ConstraintSolution& s) {
  if (completed_) return;
  VecX u;
  if (surface_->complete(u) != SolveStatus::kConverged) return;
  s.u = u;
  if (penalised_) refine(s);
  completed_ = true;
}

double FrictionalSolve::penalised_residual(const SpMat& ct, const VecX& u, const VecX& w,
                                           VecX& r_u, VecX& r_rows) const {
  r_u = p_.load - p_.stiffness * u + ct * w;
  double scale = p_.load.size() ? p_.load.cwiseAbs().maxCoeff() : 0.0;
  if (w.size()) scale = std::max(scale, w.cwiseAbs().maxCoeff());
  const int nh = static_cast<int>(last_states_.held.size());
  r_rows.resize(nh);
  double largest = r_u.size() ? r_u.cwiseAbs().maxCoeff() : 0.0;
  const VecX cu = ct.transpose() * u;
  for (int h = 0; h < nh; ++h) {
    const int r = last_states_.held[h];
    // As a force: k (target − c·u) − w, the compliance 1/k.
    r_rows[h] = (last_states_.target[h] - cu[r]) / last_states_.compliance[h] - w[r];
    largest = std::max(largest, std::abs(r_rows[h]));
  }
  return scale > 0 ? largest / scale : largest;
}

void FrictionalSolve::refine(ConstraintSolution& s) {
  const std::vector<double>& compliance = last_states_.compliance;
  if (first_row_ != 0 || last_w_.size() != me_ + 2 * m_ ||
      std::any_of(compliance.begin(), compliance.end(), [](double c) { return !(c > 0); }))
    return;
  const SpMat ct = surface_rows();
  VecX u = s.u, w = last_w_, r_u, r_rows;
  double before = penalised_residual(ct, u, w, r_u, r_rows);
  for (int step = 0; step < 3 && before > 1e-12; ++step) {
    // The correction solves the same rows with the residuals as load and targets (a slipping
    // row's force follows its normal row's exactly: no offset of its own).
    SurfaceCondensation::RowStates correction = last_states_;
    for (size_t h = 0; h < correction.held.size(); ++h)
      correction.target[h] = r_rows[static_cast<int>(h)] * correction.compliance[h];
    std::fill(correction.offset.begin(), correction.offset.end(), 0.0);
    VecX du, dw;
    double rcond = 0.0;
    if (surface_->solve(r_u, correction, dw, du, rcond) != SolveStatus::kConverged ||
        surface_->complete(du) != SolveStatus::kConverged)
      break;
    const VecX u_next = u + du, w_next = w + dw;
    VecX r_u_next, r_rows_next;
    const double after = penalised_residual(ct, u_next, w_next, r_u_next, r_rows_next);
    if (!(after < before)) break;  // no gain: the solution before this step stands
    u = u_next, w = w_next, r_u = r_u_next, r_rows = r_rows_next;
    const bool paid = after < 0.1 * before;
    before = after;
    if (!paid) break;
  }
  s.u = u;
  last_w_ = w;
  take_forces(w, s);
}

bool FrictionalSolve::all_in_play() const {
  return std::all_of(play_.begin(), play_.end(), [](char c) { return c != 0; });
}

void FrictionalSolve::count_surface_work(ConstraintSolution& s) {
  add_solver_work(surface_report(), counted_, s);
  const double dense = surface_ ? surface_->dense_seconds() : 0.0;
  s.solve_seconds += dense - dense_counted_;
  counted_ = surface_report();
  dense_counted_ = dense;
}

void FrictionalSolve::drop_surface(ConstraintSolution& s) {
  count_surface_work(s);
  surface_.reset();
  surface_tried_ = false;
  counted_ = {};
  dense_counted_ = 0.0;
}

void FrictionalSolve::choose_play(const std::vector<char>& code) {
  play_.assign(m_, 0);
  std::vector<int> open;
  int count = 0;
  for (int i = 0; i < m_; ++i) {
    play_[i] = code[i] || tresca(i) || p_.gap0[i] <= std::max(0.0, memory_.closing_reach);
    play_[i] ? void(++count) : open.push_back(i);
  }
  const int margin = std::min<int>(open.size(), std::max(8, count / 8));
  std::partial_sort(open.begin(), open.begin() + margin, open.end(),
                    [&](int a, int b) { return p_.gap0[a] < p_.gap0[b]; });
  for (int k = 0; k < margin; ++k) play_[open[k]] = 1;
  const int left_out = static_cast<int>(open.size()) - margin;
  if (count < std::max(8, m_ / 8) || left_out < std::max(48, m_ / 4)) play_.assign(m_, 1);
}

bool FrictionalSolve::bring_into_play(ConstraintSolution& s, std::vector<char>& next) {
  if (all_in_play()) return false;
  complete_displacement(s);
  const VecX g = p_.gap0 + p_.gap_jacobian * s.u;
  const VecX sl = slip(s.u);
  std::vector<char> full = next;
  const std::vector<char> play = std::exchange(play_, {});
  update(s, g, sl, full);
  play_ = play;
  double closure = 0.0;
  for (int i = 0; i < m_; ++i)
    if (play_[i]) closure = std::max(closure, p_.gap0[i] - g[i]);
  bool brought = false;
  for (int i = 0; i < m_; ++i) {
    if (play_[i] || (!full[i] && !(g[i] < 0.1 * closure))) continue;
    play_[i] = 1;
    brought = true;
    for (const int k : {i, m_ + i, 2 * m_ + i}) next[k] = full[k];
  }
  // (a third time, every row: the condensation is not made again and again)
  if (brought && ++broadened_ == 3) play_.assign(m_, 1);
  return brought;
}

}  // namespace c2d::constraints
