#include "core/tail_cholesky.hpp"

#include <cholmod.h>
#include <omp.h>

#include <algorithm>
#include <cmath>

#include "core/factor_blocks.hpp"
#include "core/stopwatch.hpp"

namespace c2d::core {

namespace {

/// Below this pivot ratio the matrix is singular to working precision (as in SpdSolver).
constexpr double kSingularPivotRatio = 1e-14;

/// A CHOLMOD view of K's lower triangle (no copy; K must be compressed).
cholmod_sparse view_lower(const SpMat& k) {
  return lower_view(static_cast<size_t>(k.rows()), static_cast<size_t>(k.nonZeros()),
                    k.outerIndexPtr(), k.innerIndexPtr(), k.valuePtr());
}

cholmod_dense view(const VecX& v) {
  cholmod_dense d{};
  d.nrow = d.d = d.nzmax = static_cast<size_t>(v.size());
  d.ncol = 1;
  d.x = const_cast<double*>(v.data());
  d.xtype = CHOLMOD_REAL;
  d.dtype = CHOLMOD_DOUBLE;
  return d;
}

}  // namespace

/// One factorisation: CHOLMOD's factor, the pattern it was analysed for, and the dense tail
/// read out of it. Shared between a TailCholesky and the cache; changed only while one holds it.
struct TailFactor {
  cholmod_common c{};
  cholmod_factor* factor = nullptr;
  std::vector<int> start, index;     ///< the analysed pattern (compressed columns)
  std::vector<int> tail;             ///< the analysed tail
  std::vector<int> tail_part;        ///< and its parts (empty: one)
  bool numeric = false;              ///< holds the numbers of a successful factorisation
  std::vector<int> tail_position;
  Eigen::MatrixXd tail_factor;
  VecX tail_pivots;
  double pivot_ratio = 0.0;

  TailFactor() {
    cholmod_start(&c);
    c.print = 0;
    c.nmethods = 1;     // the permutation, as given
    c.method[0].ordering = CHOLMOD_GIVEN;
    c.postorder = 0;    // a postorder could move tail columns before others
  }
  ~TailFactor() {
    if (factor) cholmod_free_factor(&factor, &c);
    cholmod_finish(&c);
  }
  TailFactor(const TailFactor&) = delete;
  TailFactor& operator=(const TailFactor&) = delete;

  /// Whether this factor was analysed for K's pattern (compressed), tail and parts.
  bool analysed_for(const SpMat& k, const std::vector<int>& t, const std::vector<int>& part) const {
    return factor && tail == t && tail_part == part &&
           start.size() == static_cast<size_t>(k.outerSize() + 1) &&
           index.size() == static_cast<size_t>(k.nonZeros()) &&
           std::equal(start.begin(), start.end(), k.outerIndexPtr()) &&
           std::equal(index.begin(), index.end(), k.innerIndexPtr());
  }
  /// A copy of this factor's analysis (and numbers, which the next factorisation overwrites).
  std::shared_ptr<TailFactor> copy() const {
    auto out = std::make_shared<TailFactor>();
    out->factor = cholmod_copy_factor(factor, &out->c);
    if (!out->factor) return nullptr;
    out->start = start, out->index = index, out->tail = tail, out->tail_part = tail_part;
    out->tail_position = tail_position;
    return out;
  }
};

namespace {

/// Whether two matrices of one pattern hold the same values (the caller compared patterns).
bool same_values(const SpMat& a, const SpMat& b) {
  return a.nonZeros() == b.nonZeros() &&
         std::equal(a.valuePtr(), a.valuePtr() + a.nonZeros(), b.valuePtr());
}

}  // namespace

TailFactorCache::TailFactorCache() = default;
TailFactorCache::~TailFactorCache() = default;

std::shared_ptr<const TailFactor> TailFactorCache::find(const SpMat& k, const std::vector<int>& tail,
                                                        const std::vector<int>& tail_part) const {
  for (const Entry& e : entries_)
    if (e.factor->numeric && e.factor->analysed_for(k, tail, tail_part) && same_values(k, e.k))
      return e.factor;
  return nullptr;
}

std::shared_ptr<const TailFactor> TailFactorCache::take_pattern(const SpMat& k,
                                                                const std::vector<int>& tail,
                                                                const std::vector<int>& tail_part) {
  for (auto it = entries_.begin(); it != entries_.end(); ++it)
    if (it->factor->analysed_for(k, tail, tail_part)) {
      std::shared_ptr<const TailFactor> out = std::move(it->factor);
      entries_.erase(it);
      return out;
    }
  return nullptr;
}

void TailFactorCache::keep(const SpMat& k, std::shared_ptr<const TailFactor> factor) {
  for (auto it = entries_.begin(); it != entries_.end(); ++it)
    if (it->factor == factor) {
      entries_.erase(it);
      break;
    }
  entries_.insert(entries_.begin(), Entry{k, std::move(factor)});
  entries_.front().k.makeCompressed();
  if (entries_.size() > kEntries) entries_.pop_back();
}

struct TailCholesky::Impl {
  cholmod_common c{};  ///< for the solves
  std::shared_ptr<TailFactor> f;
  SpMat compressed;                        ///< K's copy when K is not compressed
  std::shared_ptr<const FillOrder> fill;   ///< the caller's order, null for CAMD
  std::shared_ptr<TailFactorCache> cache;

  bool given(int n) const { return fill && static_cast<int>(fill->order.size()) == n; }

  Impl() {
    cholmod_start(&c);
    c.print = 0;
  }
  ~Impl() {
    f.reset();
    cholmod_finish(&c);
  }

  bool apply(int sys, const VecX& in, VecX& out) {
    cholmod_dense b = view(in);
    cholmod_dense* x = cholmod_solve(sys, f->factor, &b, &c);
    if (!x) return false;
    out = Eigen::Map<const VecX>(static_cast<double*>(x->x), in.size());
    cholmod_free_dense(&x, &c);
    return true;
  }
};

TailCholesky::TailCholesky() : impl_(std::make_unique<Impl>()) {}
TailCholesky::~TailCholesky() = default;

void TailCholesky::set_ordering(std::shared_ptr<const FillOrder> fill) {
  impl_->fill = std::move(fill);
  impl_->f.reset();  // analyse again
}

void TailCholesky::set_cache(std::shared_ptr<TailFactorCache> cache) {
  impl_->cache = std::move(cache);
}

namespace {
const std::vector<int> kNoPositions;
const Eigen::MatrixXd kNoBlock;
const VecX kNoPivots;
}  // namespace

int TailCholesky::tail_size() const {
  return impl_->f ? static_cast<int>(impl_->f->tail_factor.rows()) : 0;
}
const std::vector<int>& TailCholesky::tail_position() const {
  return impl_->f ? impl_->f->tail_position : kNoPositions;
}
const Eigen::MatrixXd& TailCholesky::tail_factor() const {
  return impl_->f ? impl_->f->tail_factor : kNoBlock;
}
const VecX& TailCholesky::tail_pivots() const {
  return impl_->f ? impl_->f->tail_pivots : kNoPivots;
}

SolveStatus TailCholesky::fail(SolveStatus status, const std::string& message) {
  report_.status = status;
  report_.message = message;
  return status;
}

std::shared_ptr<TailFactor> TailCholesky::analyse(const SpMat& k, const std::vector<int>& tail,
                                                  const std::vector<int>& tail_part) {
  Impl& m = *impl_;
  auto f = std::make_shared<TailFactor>();
  cholmod_sparse a = view_lower(k);
  // Every other unknown (set 0) before the tail (set 1): the given order partitioned so, else
  // CAMD with the two sets as constraints.
  std::vector<int> member(n_, 0), perm(n_);
  for (int d : tail) member[d] = 1;
  if (m.given(n_)) {
    auto it = perm.begin();
    for (int set = 0; set < 2; ++set)
      it = std::copy_if(m.fill->order.begin(), m.fill->order.end(), it, [&](int d) { return member[d] == set; });
  } else if (!cholmod_camd(&a, nullptr, 0, member.data(), perm.data(), &f->c)) {
    return nullptr;
  }
  if (!tail_part.empty()) {
    // The tail grouped by part, each in the order above: a part's block is the tail's only
    // coupling to it (L₂₂ block diagonal when the parts are K's unconnected pieces).
    std::vector<int> part(n_, 0);
    for (size_t i = 0; i < tail.size(); ++i) part[tail[i]] = tail_part[i];
    std::stable_sort(perm.end() - static_cast<std::ptrdiff_t>(tail.size()), perm.end(),
                     [&](int a, int b) { return part[a] < part[b]; });
  }
  f->factor = cholmod_analyze_p(&a, perm.data(), nullptr, 0, &f->c);
  if (!f->factor) return nullptr;
  f->start.assign(k.outerIndexPtr(), k.outerIndexPtr() + k.outerSize() + 1);
  f->index.assign(k.innerIndexPtr(), k.innerIndexPtr() + k.nonZeros());
  f->tail = tail;
  f->tail_part = tail_part;
  // The tail must be the factor's last k columns (no postorder moved it).
  const int* p = static_cast<const int*>(f->factor->Perm);
  const int k0 = n_ - static_cast<int>(tail.size());
  f->tail_position.assign(n_, -1);
  for (int i = k0; i < n_; ++i) f->tail_position[p[i]] = i - k0;
  for (int d : tail)
    if (f->tail_position[d] < 0) return nullptr;
  return f;
}

std::shared_ptr<TailFactor> TailCholesky::factor_for(const SpMat& k, const std::vector<int>& tail,
                                                     const std::vector<int>& tail_part) {
  Impl& m = *impl_;
  if (m.cache && (!m.f || !m.f->analysed_for(k, tail, tail_part))) {
    // The cache's factor of this pattern serves the analysis; the run has moved on from its
    // numbers, so the cache lets go of it (factorised in place below when nobody else holds it).
    if (std::shared_ptr<const TailFactor> kept = m.cache->take_pattern(k, tail, tail_part))
      m.f = std::const_pointer_cast<TailFactor>(kept);
  }
  if (m.f && m.f->analysed_for(k, tail, tail_part)) {
    if (m.f.use_count() == 1) return m.f;
    return m.f->copy();  // another holds its numbers
  }
  const Stopwatch clock;
  std::shared_ptr<TailFactor> f = analyse(k, tail, tail_part);
  report_.symbolic_analyses++;
  report_.symbolic_seconds += clock.elapsed();
  return f;
}

SolveStatus TailCholesky::factorize(const SpMat& k, const std::vector<int>& tail,
                                    const std::vector<int>& tail_part) {
  Impl& m = *impl_;
  report_.message.clear();
  report_.backend = "cholmod";
  n_ = static_cast<int>(k.rows());
  report_.ordering = m.given(n_) ? "given_tail_last" : "camd";
  if (!k.coeffs().allFinite())
    return fail(SolveStatus::kFailed, "the stiffness matrix has non-finite entries");
  const SpMat* kk = &k;
  if (!k.isCompressed()) {
    m.compressed = k;
    m.compressed.makeCompressed();
    kk = &m.compressed;
  }
  if (m.cache) {
    if (std::shared_ptr<const TailFactor> found = m.cache->find(*kk, tail, tail_part)) {
      m.f = std::const_pointer_cast<TailFactor>(found);  // shared, never changed while shared
      report_.reused_factors++;
      report_.supernodal = m.f->factor->is_super;
      report_.pivot_ratio = m.f->pivot_ratio;
      report_.status = SolveStatus::kConverged;
      return report_.status;
    }
  }
  std::shared_ptr<TailFactor> f = factor_for(*kk, tail, tail_part);
  m.f.reset();
  if (!f)
    return fail(SolveStatus::kFailed, "constrained ordering failed");
  Stopwatch clock;
  f->numeric = false;
  cholmod_sparse a = view_lower(*kk);
  int ok = 0;
  {
    // CHOLMOD's own four-thread regions stay within a one-thread budget (ActiveLevelCap).
    const ActiveLevelCap cap(omp_get_max_threads() > 1 ? 1 : 0);
    ok = cholmod_factorize(&a, f->factor, &f->c);
  }
  report_.numeric_factorizations++;
  report_.supernodal = f->factor->is_super;
  report_.factor_nonzeros = f->c.lnz;
  m.f = f;
  if (!ok || f->c.status == CHOLMOD_NOT_POSDEF || f->factor->minor < static_cast<size_t>(n_)) {
    report_.numeric_seconds += clock.lap();
    return fail(SolveStatus::kSingular, "stiffness matrix is singular or not positive definite");
  }
  f->pivot_ratio = report_.pivot_ratio = cholmod_rcond(f->factor, &f->c);
  const bool extracted = trailing_block(*f->factor, n_ - static_cast<int>(f->tail.size()),
                                        f->tail_factor, f->tail_pivots);
  report_.numeric_seconds += clock.lap();
  if (!extracted) return fail(SolveStatus::kFailed, "factor has no tail block");
  if (!(report_.pivot_ratio >= kSingularPivotRatio))
    return fail(SolveStatus::kSingular, "stiffness matrix is singular to working precision");
  f->numeric = true;
  if (m.cache) m.cache->keep(*kk, f);
  report_.status = SolveStatus::kConverged;
  return report_.status;
}

SolveStatus TailCholesky::apply_pair(int first, int second, const VecX& in, VecX& out,
                                     const char* what) {
  if (report_.status != SolveStatus::kConverged) return report_.status;
  const Stopwatch clock;
  VecX mid;
  const bool ok = impl_->apply(first, in, mid) && impl_->apply(second, mid, out);
  report_.solve_seconds += clock.elapsed();
  if (!ok || !out.allFinite()) return fail(SolveStatus::kFailed, std::string(what) + " failed");
  return SolveStatus::kConverged;
}

SolveStatus TailCholesky::forward(const VecX& b, VecX& w) {
  return apply_pair(CHOLMOD_P, CHOLMOD_LD, b, w, "forward substitution");
}

SolveStatus TailCholesky::backward(const VecX& w, VecX& x) {
  return apply_pair(CHOLMOD_Lt, CHOLMOD_Pt, w, x, "back substitution");
}

}  // namespace c2d::core
