#include "core/tail_cholesky.hpp"

#include <cholmod.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <mutex>

#include "core/factor_blocks.hpp"
#include "core/sparse_pattern.hpp"
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

struct TailAnalyses::Impl {
  /// How many analyses are kept: a load step's first iterate may condense every row and the
  /// next ones the rows in play, so two tails alternate.
  static constexpr size_t kKept = 3;
  struct Entry {
    std::shared_ptr<const FillOrder> fill;  ///< held, so that its address names it
    std::shared_ptr<const AnalysedPattern> pattern;  ///< shared with the factors that use it
    std::vector<int> tail, tail_part;
    cholmod_factor* symbolic = nullptr;
    double lnz = 0;  ///< the factor's nonzeros, as the analysis counted them
    const char* ordering = "";  ///< the order's name (TailCholesky's report)
  };
  std::mutex mutex;
  cholmod_common c{};
  std::deque<Entry> entries;  ///< the latest first

  Impl() {
    cholmod_start(&c);
    c.print = 0;
  }
  ~Impl() {
    for (Entry& e : entries) cholmod_free_factor(&e.symbolic, &c);
    cholmod_finish(&c);
  }
  /// A copy (allocated through `into`) of the analysis kept for these, or null; `pattern` the
  /// kept pattern.
  cholmod_factor* copy(const SpMat& k, const std::vector<int>& tail,
                       const std::vector<int>& tail_part, const FillOrder* fill,
                       cholmod_common* into, std::shared_ptr<const AnalysedPattern>& pattern,
                       const char*& ordering) {
    const std::lock_guard<std::mutex> lock(mutex);
    for (const Entry& e : entries)
      if (e.fill.get() == fill && e.tail == tail && e.tail_part == tail_part &&
          e.pattern->matches(k)) {
        into->lnz = e.lnz;
        pattern = e.pattern;
        ordering = e.ordering;
        return cholmod_copy_factor(e.symbolic, into);
      }
    return nullptr;
  }
  /// Keeps a copy of `symbolic` (not yet factorised), the oldest kept analysis making room.
  void keep(std::shared_ptr<const AnalysedPattern> pattern, const std::vector<int>& tail,
            const std::vector<int>& tail_part, const std::shared_ptr<const FillOrder>& fill,
            cholmod_factor* symbolic, double lnz, const char* ordering) {
    const std::lock_guard<std::mutex> lock(mutex);
    Entry e{fill,    std::move(pattern), tail, tail_part, cholmod_copy_factor(symbolic, &c), lnz,
            ordering};
    if (!e.symbolic) return;
    if (entries.size() == kKept) {
      cholmod_free_factor(&entries.back().symbolic, &c);
      entries.pop_back();
    }
    entries.push_front(std::move(e));
  }
};

TailAnalyses::TailAnalyses() : impl_(std::make_unique<Impl>()) {}
TailAnalyses::~TailAnalyses() = default;

struct TailCholesky::Impl {
  cholmod_common c{};
  cholmod_factor* factor = nullptr;
  std::shared_ptr<const AnalysedPattern> pattern;  ///< the analysed pattern
  std::vector<int> tail;             ///< the analysed tail
  std::vector<int> tail_part;        ///< and its parts (empty: one)
  SpMat compressed;                  ///< K's copy when K is not compressed
  std::shared_ptr<const FillOrder> fill;  ///< the caller's order, null for CAMD
  std::shared_ptr<TailAnalyses> analyses;  ///< shared analyses, null: none
  const char* ordering = "";               ///< the analysed order's name

  bool given(int n) const { return fill && static_cast<int>(fill->order.size()) == n; }
  bool analysed_for(const SpMat& k) const { return factor && pattern && pattern->matches(k); }
  void keep_pattern(const SpMat& k) {
    auto kept = std::make_shared<AnalysedPattern>();
    kept->keep(k);
    pattern = std::move(kept);
  }

  Impl() {
    cholmod_start(&c);
    c.print = 0;
    c.nmethods = 1;     // the CAMD permutation, as given
    c.method[0].ordering = CHOLMOD_GIVEN;
    c.postorder = 0;    // a postorder could move tail columns before others
  }
  ~Impl() {
    if (factor) cholmod_free_factor(&factor, &c);
    cholmod_finish(&c);
  }
  /// Applies `sys` (CHOLMOD_P, _L, _Lt, _Pt) to `in`.
  bool apply(int sys, const VecX& in, VecX& out) {
    cholmod_dense b = view(in);
    cholmod_dense* x = cholmod_solve(sys, factor, &b, &c);
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
  impl_->pattern.reset();  // analyse again
}

void TailCholesky::set_analyses(std::shared_ptr<TailAnalyses> analyses) {
  impl_->analyses = std::move(analyses);
}

SolveStatus TailCholesky::fail(SolveStatus status, const std::string& message) {
  report_.status = status;
  report_.message = message;
  return status;
}

void TailCholesky::group_tail(const std::vector<int>& tail, std::vector<int>& perm) const {
  const std::vector<int>& tail_part = impl_->tail_part;
  if (tail_part.empty()) return;
  // The tail grouped by part, each in the order given: a part's block is the tail's only
  // coupling to it (L₂₂ block diagonal when the parts are K's unconnected pieces).
  std::vector<int> part(n_, 0);
  for (size_t i = 0; i < tail.size(); ++i) part[tail[i]] = tail_part[i];
  std::stable_sort(perm.end() - static_cast<std::ptrdiff_t>(tail.size()), perm.end(),
                   [&](int a, int b) { return part[a] < part[b]; });
}

bool TailCholesky::analyse(const SpMat& k, const std::vector<int>& tail) {
  Impl& m = *impl_;
  if (m.factor) cholmod_free_factor(&m.factor, &m.c);
  cholmod_sparse a = view_lower(k);
  // Every other unknown (set 0) before the tail (set 1). With a given fill order, the one of
  // its two tail-last orders whose factor takes fewer flops (FillOrder::tail_last, moved_last);
  // else CAMD on K with the two sets as constraints.
  std::vector<std::pair<const char*, std::vector<int>>> orders;
  if (m.given(n_)) {
    orders.emplace_back("given_tail_last", m.fill->moved_last(tail));
    if (std::vector<int> camd = m.fill->tail_last(tail); !camd.empty())
      orders.emplace_back("corner_camd", std::move(camd));
  } else {
    std::vector<int> member(n_, 0), perm(n_);
    for (int d : tail) member[d] = 1;
    if (!cholmod_camd(&a, nullptr, 0, member.data(), perm.data(), &m.c)) return false;
    orders.emplace_back("camd", std::move(perm));
  }
  double flops = 0, lnz = 0;
  for (auto& [name, perm] : orders) {
    group_tail(tail, perm);
    cholmod_factor* f = cholmod_analyze_p(&a, perm.data(), nullptr, 0, &m.c);
    if (!f) return false;
    if (m.factor && m.c.fl >= flops) {
      cholmod_free_factor(&f, &m.c);
      continue;
    }
    if (m.factor) cholmod_free_factor(&m.factor, &m.c);
    m.factor = f;
    m.ordering = name;
    flops = m.c.fl;
    lnz = m.c.lnz;
  }
  m.c.fl = flops;
  m.c.lnz = lnz;
  m.keep_pattern(k);
  m.tail = tail;
  if (!place_tail(tail)) return false;
  const std::shared_ptr<const FillOrder> fill = m.given(n_) ? m.fill : nullptr;
  if (m.analyses)
    m.analyses->impl_->keep(m.pattern, tail, m.tail_part, fill, m.factor, m.c.lnz, m.ordering);
  return true;
}

bool TailCholesky::adopt(const SpMat& k, const std::vector<int>& tail) {
  Impl& m = *impl_;
  if (!m.analyses) return false;
  std::shared_ptr<const AnalysedPattern> pattern;
  cholmod_factor* copy = m.analyses->impl_->copy(
      k, tail, m.tail_part, m.given(n_) ? m.fill.get() : nullptr, &m.c, pattern, m.ordering);
  if (!copy) return false;
  if (m.factor) cholmod_free_factor(&m.factor, &m.c);
  m.factor = copy;
  m.pattern = std::move(pattern);
  m.tail = tail;
  return place_tail(tail);
}

bool TailCholesky::place_tail(const std::vector<int>& tail) {
  // The tail must be the factor's last k columns (no postorder moved it).
  const int* p = static_cast<const int*>(impl_->factor->Perm);
  const int k0 = n_ - static_cast<int>(tail.size());
  tail_position_.assign(n_, -1);
  for (int i = k0; i < n_; ++i) tail_position_[p[i]] = i - k0;
  for (int d : tail)
    if (tail_position_[d] < 0) return false;
  return true;
}

SolveStatus TailCholesky::factorize(const SpMat& k, const std::vector<int>& tail,
                                    const std::vector<int>& tail_part) {
  Impl& m = *impl_;
  if (tail_part != m.tail_part) m.tail_part = tail_part, m.pattern.reset();  // analyse again
  report_.message.clear();
  report_.backend = "cholmod";
  n_ = static_cast<int>(k.rows());
  if (!k.coeffs().allFinite())
    return fail(SolveStatus::kFailed, "the stiffness matrix has non-finite entries");
  const SpMat* kk = &k;
  if (!k.isCompressed()) {
    m.compressed = k;
    m.compressed.makeCompressed();
    kk = &m.compressed;
  }
  Stopwatch clock;
  if (!m.analysed_for(*kk) || m.tail != tail) {
    const bool adopted = adopt(*kk, tail);
    const bool ok = adopted || analyse(*kk, tail);
    if (!adopted) report_.symbolic_analyses++;
    report_.symbolic_seconds += clock.lap();
    report_.ordering = m.ordering;
    if (!ok) {
      m.pattern.reset();
      return fail(SolveStatus::kFailed, "constrained ordering failed (CHOLMOD status " +
                                            std::to_string(m.c.status) + ")");
    }
  }
  cholmod_sparse a = view_lower(*kk);
  int ok = 0;
  {
    // CHOLMOD's own four-thread regions stay within a one-thread budget (ActiveLevelCap).
    const ActiveLevelCap cap(omp_get_max_threads() > 1 ? 1 : 0);
    ok = cholmod_factorize(&a, m.factor, &m.c);
  }
  report_.numeric_factorizations++;
  report_.supernodal = m.factor->is_super;
  report_.factor_nonzeros = m.c.lnz;
  if (!ok || m.c.status == CHOLMOD_NOT_POSDEF || m.factor->minor < static_cast<size_t>(n_)) {
    report_.numeric_seconds += clock.lap();
    return fail(SolveStatus::kSingular, "stiffness matrix is singular or not positive definite");
  }
  report_.pivot_ratio = cholmod_rcond(m.factor, &m.c);
  const bool extracted = extract_tail_factor();
  report_.numeric_seconds += clock.lap();
  if (!extracted) return fail(SolveStatus::kFailed, "factor has no tail block");
  if (!(report_.pivot_ratio >= kSingularPivotRatio))
    return fail(SolveStatus::kSingular, "stiffness matrix is singular to working precision");
  report_.status = SolveStatus::kConverged;
  return report_.status;
}

bool TailCholesky::extract_tail_factor() {
  return trailing_block(*impl_->factor, n_ - static_cast<int>(impl_->tail.size()), tail_factor_,
                        tail_pivots_);
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
