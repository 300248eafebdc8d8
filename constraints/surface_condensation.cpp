#include "constraints/surface_condensation.hpp"

#include <algorithm>
#include <cmath>

#include "core/stopwatch.hpp"

namespace c2d::constraints {

namespace {
/// Below this pivot ratio K_ρ is taken as singular: S would be meaningless (as the
/// saddle-point solver's).
constexpr double kMinPivotRatio = 1e-11;
/// A regularising row's equation in the dense block whose every entry is below this fraction
/// of its largest term cancelled to round-off: the auxiliary force ζ_q is the only thing holding
/// a rigid mode (S_qq = 1/ρ_q exactly), and the block is singular whatever its pivots say.
/// Measured: such a block cancels to 1e-10 of its terms, with an LU rcond of 0.15; a row that
/// K supports keeps S_qq ≤ 1/ρ_q by a fraction of one.
constexpr double kCancelled = 1e-8;
}  // namespace

SpMat regularised_stiffness(const SpMat& k, const SpMat& ct, const std::vector<int>& rows,
                            VecX& rho) {
  const VecX diag = k.diagonal();
  rho = VecX::Zero(ct.cols());
  std::vector<Triplet> t;
  for (int q : rows) {
    double a2 = 0.0, ak = 0.0;
    for (SpMat::InnerIterator it(ct, q); it; ++it) {
      a2 += it.value() * it.value();
      ak += it.value() * it.value() * diag[it.row()];
    }
    if (!(a2 > 0) || !(ak > 0)) continue;
    rho[q] = ak / (a2 * a2);
    const double sq = std::sqrt(rho[q]);
    for (SpMat::InnerIterator it(ct, q); it; ++it) t.emplace_back(q, it.row(), sq * it.value());
  }
  SpMat scaled(ct.cols(), ct.rows());
  scaled.setFromTriplets(t.begin(), t.end());
  return k + SpMat(scaled.transpose() * scaled);
}

std::unique_ptr<SurfaceCondensation> condense_onto_rows(
    SpMat ct, const SpMat& k, std::shared_ptr<const core::FillOrder> ordering,
    std::shared_ptr<core::TailAnalyses> analyses, const std::vector<int>& always,
    std::vector<std::vector<int>> groups, const std::vector<double>& gap, bool anchor,
    bool* unfactorised) {
  auto surface = std::make_unique<SurfaceCondensation>(std::move(ct), std::move(ordering),
                                                       std::move(analyses));
  if (!surface->fits()) return nullptr;
  if (anchor && surface->factorize(k, always, true)) return surface;
  const int count = static_cast<int>(groups.size());
  std::vector<int> order(count);
  for (int g = 0; g < count; ++g) order[g] = g;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return gap[a] < gap[b]; });
  for (const int first : {8, count}) {
    std::vector<int> reg = always;
    for (int g = 0; g < std::min(first, count); ++g)
      reg.insert(reg.end(), groups[order[g]].begin(), groups[order[g]].end());
    if (surface->factorize(k, reg)) return surface;
    if (first >= count) break;
  }
  if (unfactorised) *unfactorised = true;
  return nullptr;
}

namespace {

/// Connected parts of the unknowns: joined by K's entries and by each of the rows `rows` of ct.
class Parts {
 public:
  Parts(const SpMat& k, const SpMat& ct, const std::vector<int>& rows) : up_(k.rows()) {
    for (int d = 0; d < k.rows(); ++d) up_[d] = d;
    for (int c = 0; c < k.outerSize(); ++c)
      for (SpMat::InnerIterator it(k, c); it; ++it) join(static_cast<int>(it.row()), c);
    for (int r : rows) {
      int first = -1;
      for (SpMat::InnerIterator it(ct, r); it; ++it)
        first < 0 ? void(first = static_cast<int>(it.row())) : join(first, static_cast<int>(it.row()));
    }
  }
  int of(int d) {
    while (up_[d] != d) d = up_[d] = up_[up_[d]];
    return d;
  }

 private:
  void join(int a, int b) {
    a = of(a), b = of(b);
    if (a != b) up_[std::max(a, b)] = std::min(a, b);
  }
  std::vector<int> up_;
};

}  // namespace

SurfaceCondensation::SurfaceCondensation(SpMat ct, std::shared_ptr<const core::FillOrder> ordering,
                                         std::shared_ptr<core::TailAnalyses> analyses)
    : user_ct_(std::move(ct)), rows_(static_cast<int>(user_ct_.cols())), ct_(user_ct_) {
  user_ct_.makeCompressed();
  ct_.makeCompressed();
  slot_.assign(ct_.cols(), -1);
  std::vector<char> touched(ct_.rows(), 0);
  for (int c = 0; c < ct_.outerSize(); ++c)
    for (SpMat::InnerIterator it(ct_, c); it; ++it) touched[it.row()] = 1;
  for (int d = 0; d < ct_.rows(); ++d)
    if (touched[d]) tail_dofs_.push_back(d);
  block_start_ = {0, static_cast<int>(tail_dofs_.size())};
  if (ordering) tail_.set_ordering(std::move(ordering));
  tail_.set_analyses(std::move(analyses));
}

std::vector<int> SurfaceCondensation::set_anchors(const std::vector<int>& regularise, bool anchor) {
  std::vector<int> reg = regularise;
  if (!anchor) {
    ct_ = user_ct_;
    return reg;
  }
  // Per part: the tail unknowns of its first and last tail node (node = unknown / 2), enough for
  // its rigid motions when both displacements are there, or the in-plane turn and translation
  // of a surface whose rows touch one component (a flat's gaps: u_y only). Each anchor row is
  // one unknown's: it joins no parts.
  std::vector<int> first(user_ct_.rows(), -1), last(user_ct_.rows(), -1);
  for (size_t i = 0; i < tail_dofs_.size(); ++i) {
    const int part = tail_part_[i], node = tail_dofs_[i] / 2;
    if (first[part] < 0) first[part] = node;
    last[part] = node;
  }
  std::vector<Triplet> t;
  for (int c = 0; c < user_ct_.outerSize(); ++c)
    for (SpMat::InnerIterator it(user_ct_, c); it; ++it) t.emplace_back(it.row(), c, it.value());
  int col = rows_;
  for (size_t i = 0; i < tail_dofs_.size(); ++i) {
    const int d = tail_dofs_[i], part = tail_part_[i];
    if (d / 2 != first[part] && d / 2 != last[part]) continue;
    t.emplace_back(d, col, 1.0);
    reg.push_back(col++);
  }
  ct_.resize(user_ct_.rows(), col);
  ct_.setFromTriplets(t.begin(), t.end());
  return reg;
}

void SurfaceCondensation::find_blocks() {
  // The factor's tail is grouped by part (TailCholesky): a block starts where the part changes.
  const auto& pos = tail_.tail_position();
  std::vector<int> part_at(tail_dofs_.size());
  for (size_t i = 0; i < tail_dofs_.size(); ++i) part_at[pos[tail_dofs_[i]]] = tail_part_[i];
  block_start_ = {0};
  for (size_t i = 1; i < part_at.size(); ++i)
    if (part_at[i] != part_at[i - 1]) block_start_.push_back(static_cast<int>(i));
  block_start_.push_back(static_cast<int>(part_at.size()));
}

SurfaceCondensation::~SurfaceCondensation() = default;

int SurfaceCondensation::add_rows(const SpMat& more) {
  if (!factored_ || ct_.cols() != rows_ || more.rows() != ct_.rows() ||
      rows_ + more.cols() > kMaxRows)
    return -1;
  const std::vector<int>& pos = tail_.tail_position();
  std::vector<Triplet> t;
  t.reserve(static_cast<size_t>(ct_.nonZeros() + more.nonZeros()));
  for (int c = 0; c < ct_.outerSize(); ++c)
    for (SpMat::InnerIterator it(ct_, c); it; ++it) t.emplace_back(it.row(), c, it.value());
  for (int c = 0; c < more.outerSize(); ++c)
    for (SpMat::InnerIterator it(more, c); it; ++it) {
      if (pos[it.row()] < 0) return -1;
      t.emplace_back(it.row(), rows_ + c, it.value());
    }
  const int first = rows_;
  rows_ += static_cast<int>(more.cols());
  ct_.resize(ct_.rows(), rows_);
  ct_.setFromTriplets(t.begin(), t.end());
  user_ct_ = ct_;
  rho_.conservativeResize(rows_);
  rho_.tail(rows_ - first).setZero();
  slot_.resize(rows_, -1);
  return first;
}

bool SurfaceCondensation::fits() const {
  const int kt = static_cast<int>(tail_dofs_.size());
  return kt > 0 && kt <= kMaxTail && kt < ct_.rows() && ct_.cols() <= kMaxRows;
}

bool SurfaceCondensation::factorize(const SpMat& k, const std::vector<int>& regularise,
                                    bool anchor) {
  factored_ = false;
  known_.clear();
  v_.resize(0, 0);
  s_.resize(0, 0);
  cached_f_.resize(0);
  if (!fits()) {
    message_ = "the rows touch too many unknowns for a dense surface block";
    return false;
  }
  // The parts K and the caller's regularising rows join (anchor rows join none): the factor's
  // tail is grouped by them.
  Parts parts(k, user_ct_, regularise);
  tail_part_.resize(tail_dofs_.size());
  for (size_t i = 0; i < tail_dofs_.size(); ++i) tail_part_[i] = parts.of(tail_dofs_[i]);
  const std::vector<int> reg = set_anchors(regularise, anchor);
  slot_.assign(ct_.cols(), -1);
  k_rho_ = regularised_stiffness(k, ct_, reg, rho_);
  if (tail_.factorize(k_rho_, tail_dofs_, tail_part_) != SolveStatus::kConverged ||
      !(tail_.report().pivot_ratio > kMinPivotRatio)) {
    message_ = tail_.report().message.empty() ? "K_ρ is singular to working precision"
                                              : tail_.report().message;
    return false;
  }
  find_blocks();
  message_.clear();
  factored_ = true;
  return true;
}

void SurfaceCondensation::prepare(const std::vector<int>& rows) {
  const auto& pos = tail_.tail_position();
  const int kt = tail_.tail_size();
  std::vector<int> fresh;
  for (int r : rows)
    if (slot_[r] < 0) {
      slot_[r] = static_cast<int>(known_.size() + fresh.size());
      fresh.push_back(r);
    }
  if (fresh.empty()) return;
  const core::Stopwatch clock;
  const int old = static_cast<int>(known_.size());
  const int nf = static_cast<int>(fresh.size()), all = old + nf;
  Eigen::MatrixXd block = Eigen::MatrixXd::Zero(kt, nf);
  for (int c = 0; c < nf; ++c)
    for (SpMat::InnerIterator it(ct_, fresh[c]); it; ++it) block(pos[it.row()], c) = it.value();
  known_.insert(known_.end(), fresh.begin(), fresh.end());
  // Per diagonal block [b0, b1) of L₂₂ (a part of the tail), the new columns that reach it, by
  // where they start in it, in chunks: a chunk starting at p needs L₂₂[p:b1, p:b1] only, and
  // its S entries sum over the rows p..b1 (V is zero above a column's start, D₂⁻¹ diagonal).
  struct Chunk {
    int p, end;  ///< its rows p..end of its block
    std::vector<int> cols;
    std::vector<int> earlier;  ///< the new columns of its block's earlier chunks
  };
  std::vector<Chunk> chunks;
  for (size_t b = 0; b + 1 < block_start_.size(); ++b) {
    const int b0 = block_start_[b], b1 = block_start_[b + 1];
    std::vector<std::pair<int, int>> reach;  // (start, column)
    for (int c = 0; c < nf; ++c) {
      int start = b1;
      for (SpMat::InnerIterator it(ct_, fresh[c]); it; ++it) {
        const int at = pos[it.row()];
        if (at >= b0 && at < b1) start = std::min(start, at);
      }
      if (start < b1) reach.emplace_back(start, c);
    }
    std::sort(reach.begin(), reach.end());
    const int count = static_cast<int>(reach.size()), pieces = std::min(count, 8);
    std::vector<int> so_far;
    for (int q = 0; q < pieces; ++q) {
      Chunk chunk{reach[q * count / pieces].first, b1, {}, so_far};
      for (int i = q * count / pieces; i < (q + 1) * count / pieces; ++i)
        chunk.cols.push_back(reach[i].second);
      const int h = b1 - chunk.p, w = static_cast<int>(chunk.cols.size());
      Eigen::MatrixXd part(h, w);
      for (int j = 0; j < w; ++j) part.col(j) = block.col(chunk.cols[j]).segment(chunk.p, h);
      tail_.tail_factor().block(chunk.p, chunk.p, h, h).triangularView<Eigen::Lower>().solveInPlace(part);
      for (int j = 0; j < w; ++j) block.col(chunk.cols[j]).segment(chunk.p, h) = part.col(j);
      so_far.insert(so_far.end(), chunk.cols.begin(), chunk.cols.end());
      chunks.push_back(std::move(chunk));
    }
  }
  v_.conservativeResize(kt, all);
  v_.rightCols(nf) = block;
  s_.conservativeResize(all, all);
  s_.rightCols(nf).setZero();
  // S's new columns: against the known columns in full; among the new ones each pair once per
  // block, in the later chunk's product (the earlier chunk's column is dense over its rows),
  // a chunk's own square halved, so that S_new = A + Aᵀ: half the products of Vᵀ D₂⁻¹ V.
  const VecX inverse_pivots = tail_.tail_pivots().cwiseInverse();
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(nf, nf);
  for (const Chunk& chunk : chunks) {
    const int p = chunk.p, h = chunk.end - p, w = static_cast<int>(chunk.cols.size());
    const int ne = static_cast<int>(chunk.earlier.size());
    Eigen::MatrixXd scaled(h, w), rows(h, ne + w);
    for (int j = 0; j < w; ++j) {
      rows.col(ne + j) = block.col(chunk.cols[j]).segment(p, h);
      scaled.col(j) = inverse_pivots.segment(p, h).cwiseProduct(rows.col(ne + j));
    }
    for (int e = 0; e < ne; ++e) rows.col(e) = block.col(chunk.earlier[e]).segment(p, h);
    if (old > 0) {
      const Eigen::MatrixXd add = v_.block(p, 0, h, old).transpose() * scaled;  // old × w
      for (int j = 0; j < w; ++j) s_.col(old + chunk.cols[j]).head(old) += add.col(j);
    }
    const Eigen::MatrixXd add = rows.transpose() * scaled;  // (ne + w) × w
    for (int j = 0; j < w; ++j) {
      const int cj = chunk.cols[j];
      for (int e = 0; e < ne; ++e) a(chunk.earlier[e], cj) += add(e, j);
      for (int i = 0; i < w; ++i) a(chunk.cols[i], cj) += 0.5 * add(ne + i, j);
    }
  }
  s_.bottomRightCorner(nf, nf) = a + a.transpose();
  s_.bottomLeftCorner(nf, old) = s_.topRightCorner(old, nf).transpose();
  dense_seconds_ += clock.elapsed();
}

Eigen::MatrixXd SurfaceCondensation::schur(const std::vector<int>& rows,
                                           const std::vector<int>& cols) {
  std::vector<int> both = rows;
  both.insert(both.end(), cols.begin(), cols.end());
  prepare(both);
  Eigen::MatrixXd out(rows.size(), cols.size());
  for (size_t c = 0; c < cols.size(); ++c)
    for (size_t r = 0; r < rows.size(); ++r) out(r, c) = s_(slot_[rows[r]], slot_[cols[c]]);
  return out;
}

SolveStatus SurfaceCondensation::forward(const VecX& f) {
  if (f.size() == cached_f_.size() && f == cached_f_) return SolveStatus::kConverged;
  cached_f_.resize(0);
  const SolveStatus st = tail_.forward(f, forward_);
  if (st != SolveStatus::kConverged) {
    message_ = tail_.report().message;
    return st;
  }
  cached_f_ = f;
  return st;
}

SolveStatus SurfaceCondensation::rest_values(const VecX& f, const std::vector<int>& rows,
                                             VecX& y0) {
  if (!factored_) return SolveStatus::kFailed;
  if (const SolveStatus st = forward(f); st != SolveStatus::kConverged) return st;
  prepare(rows);
  const int kt = tail_.tail_size();
  y0.resize(static_cast<int>(rows.size()));
  for (size_t r = 0; r < rows.size(); ++r)
    y0[static_cast<int>(r)] = v_.col(slot_[rows[r]]).dot(forward_.tail(kt));
  return SolveStatus::kConverged;
}

SolveStatus SurfaceCondensation::displacement(const VecX& f, const std::vector<int>& cols,
                                              const VecX& w, VecX& u, bool tail_only) {
  if (!factored_) return SolveStatus::kFailed;
  if (const SolveStatus st = forward(f); st != SolveStatus::kConverged) return st;
  prepare(cols);
  const core::Stopwatch clock;
  const int kt = tail_.tail_size();
  VecX pushed = VecX::Zero(kt);
  for (size_t c = 0; c < cols.size(); ++c) pushed += w[static_cast<int>(c)] * v_.col(slot_[cols[c]]);
  VecX forward = forward_;
  forward.tail(kt) += pushed.cwiseQuotient(tail_.tail_pivots());
  if (tail_only) {
    VecX ut = forward.tail(kt);
    for (size_t b = 0; b + 1 < block_start_.size(); ++b) {
      const int b0 = block_start_[b], h = block_start_[b + 1] - b0;
      auto segment = ut.segment(b0, h);
      tail_.tail_factor().block(b0, b0, h, h).triangularView<Eigen::Lower>().transpose().solveInPlace(
          segment);
    }
    u = VecX::Zero(ct_.rows());
    for (int d : tail_dofs_) u[d] = ut[tail_.tail_position()[d]];
    dense_seconds_ += clock.elapsed();
    return u.allFinite() ? SolveStatus::kConverged : SolveStatus::kFailed;
  }
  dense_seconds_ += clock.elapsed();
  const SolveStatus st = tail_.backward(forward, u);
  if (st != SolveStatus::kConverged) message_ = tail_.report().message;
  return st;
}

SolveStatus SurfaceCondensation::solve(const VecX& f, const RowStates& states, VecX& force,
                                        VecX& u, double& rcond) {
  if (!factored_) return SolveStatus::kFailed;
  const int rows = static_cast<int>(ct_.cols());
  const int nh = static_cast<int>(states.held.size());
  std::vector<int> x_of(rows, -1);  // a held row's unknown in X
  for (int h = 0; h < nh; ++h) x_of[states.held[h]] = h;
  // The regularising rows that need an auxiliary force of their own. A held row that
  // regularises needs none: its two equations, (S W)_r + compliance_r w_r = target_r − y0_r and
  // (S W)_r − ζ_r/ρ_r = −y0_r, give ζ_r = ρ_r (target_r − compliance_r w_r), so its column of W
  // is (1 − ρ_r compliance_r) w_r + ρ_r target_r and the second equation is the first. (A body
  // held only by its contact regularises every contact row: this halves the dense block.)
  std::vector<int> reg;
  for (int r = 0; r < rows; ++r)
    if (rho_[r] > 0 && x_of[r] < 0) reg.push_back(r);
  const int nr = static_cast<int>(reg.size());
  // W over the columns J (rows that may carry a force, ζ folded into its row's column):
  // W_J = B X + W0 with X = [w_H; ζ].
  std::vector<int> cols, col_of(rows, -1);
  auto col = [&](int r) {
    if (col_of[r] < 0) col_of[r] = static_cast<int>(cols.size()), cols.push_back(r);
    return col_of[r];
  };
  std::vector<BlockEntry> b_map;
  std::vector<std::pair<int, double>> w0;
  for (int h = 0; h < nh; ++h) {
    const int r = states.held[h];
    const double rho = rho_[r];
    b_map.push_back({col(r), h, 1.0 - rho * states.compliance[h]});
    if (rho > 0 && states.target[h] != 0.0) w0.emplace_back(col(r), rho * states.target[h]);
  }
  for (int q = 0; q < nr; ++q) b_map.push_back({col(reg[q]), nh + q, 1.0});
  for (size_t k = 0; k < states.following.size(); ++k) {
    const int c = col(states.following[k]), lead = states.leader[k];
    w0.emplace_back(c, states.offset[k]);
    if (lead >= 0 && x_of[lead] >= 0 && states.factor[k] != 0.0)
      b_map.push_back({c, x_of[lead], states.factor[k]});
  }
  // The equations: held row r, (S W)_r + compliance_r w_r = target_r − y0_r; regularising row
  // q, (S W)_q − ζ_q/ρ_q = −y0_q (y0 = C K_ρ⁻¹ f).
  std::vector<int> eqs = states.held;
  eqs.insert(eqs.end(), reg.begin(), reg.end());
  const Eigen::MatrixXd s_ej = schur(eqs, cols);
  VecX y0;
  if (const SolveStatus st = rest_values(f, eqs, y0); st != SolveStatus::kConverged) return st;
  const core::Stopwatch clock;
  const int nx = nh + nr;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(nx, nx);
  for (const BlockEntry& e : b_map) a.col(e.x) += e.v * s_ej.col(e.col);
  VecX b = -y0;
  for (int h = 0; h < nh; ++h) a(h, h) += states.compliance[h], b[h] += states.target[h];
  for (int q = 0; q < nr; ++q) a(nh + q, nh + q) -= 1.0 / rho_[reg[q]];
  for (const auto& [c, v] : w0) b -= v * s_ej.col(c);
  VecX x = VecX::Zero(nx);
  rcond = 1.0;
  relative_residual_ = 0.0;
  if (cancels(a, s_ej, b_map, nh, reg)) {
    dense_seconds_ += clock.elapsed();
    rcond = 0.0;
    message_ = "the rows' condensed block is singular: a body moves freely beside its rows "
               "(its regularising row's equation cancels to round-off)";
    return SolveStatus::kSingular;
  }
  if (nx > 0) {
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(a);
    const VecX d = lu.matrixLU().diagonal().cwiseAbs();
    const double dmax = d.maxCoeff();
    // (pivots against the regularising rows' terms too: a block that cancels as a whole has
    // small pivots of even size)
    double terms = dmax;
    for (int q = 0; q < nr; ++q) terms = std::max(terms, 1.0 / rho_[reg[q]]);
    rcond = dmax > 0 && d.allFinite() ? std::min(lu.rcond(), d.minCoeff() / terms) : 0.0;
    if (!(rcond > 1e-13)) {
      dense_seconds_ += clock.elapsed();
      message_ = "the rows' condensed block is singular: linearly dependent rows or an "
                 "unsupported body";
      return SolveStatus::kSingular;
    }
    x = lu.solve(b);
    const double bn = b.norm();
    relative_residual_ = (a * x - b).norm() / (bn > 0 ? bn : 1.0);
    if (!x.allFinite() || !(relative_residual_ <= 1e-8)) {
      dense_seconds_ += clock.elapsed();
      message_ = "the rows' condensed block solves to no precision";
      return SolveStatus::kIllConditioned;
    }
  }
  last_w_ = VecX::Zero(static_cast<int>(cols.size()));
  for (const BlockEntry& e : b_map) last_w_[e.col] += e.v * x[e.x];
  for (const auto& [c, v] : w0) last_w_[c] += v;
  last_cols_ = cols;
  force = VecX::Zero(rows_);
  for (int h = 0; h < nh; ++h) force[states.held[h]] = x[h];
  for (size_t k = 0; k < states.following.size(); ++k) {
    const int lead = states.leader[k];
    force[states.following[k]] =
        states.offset[k] + (lead >= 0 && x_of[lead] >= 0 ? states.factor[k] * x[x_of[lead]] : 0.0);
  }
  dense_seconds_ += clock.elapsed();
  return displacement(f, last_cols_, last_w_, u, true);
}

bool SurfaceCondensation::cancels(const Eigen::MatrixXd& a, const Eigen::MatrixXd& s_ej,
                                  const std::vector<BlockEntry>& b_map, int nh,
                                  const std::vector<int>& reg) const {
  const int nr = static_cast<int>(reg.size());
  VecX terms = VecX::Zero(nr);  // per regularising equation: its largest term
  for (const BlockEntry& e : b_map)
    for (int q = 0; q < nr; ++q)
      terms[q] = std::max(terms[q], std::abs(e.v * s_ej(nh + q, e.col)));
  for (int q = 0; q < nr; ++q) {
    const double scale = std::max(terms[q], 1.0 / rho_[reg[q]]);
    if (a.row(nh + q).cwiseAbs().maxCoeff() < kCancelled * scale) return true;
  }
  return false;
}

SolveStatus SurfaceCondensation::complete(VecX& u) {
  return displacement(cached_f_, last_cols_, last_w_, u, false);
}

}  // namespace c2d::constraints
