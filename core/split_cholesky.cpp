#include "core/split_cholesky.hpp"

#include <cholmod.h>
#include <dlfcn.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <mutex>
#include <new>
#include <numeric>

#include "core/factor_blocks.hpp"

namespace c2d::core {

namespace {

/// OpenBLAS on one thread while the halves factorise (side by side, OpenBLAS's own threads
/// would compete for the same cores; and one after the other, the halves' numbers then do not
/// depend on the thread count), restored after. Looked up at run time: another BLAS
/// (reference, BLIS) has no such call and is left as it is. OpenBLAS's count is the process's:
/// with factorisations in several threads at once (the Python module), the first in saves it
/// and the last out restores it.
class SerialBlas {
 public:
  SerialBlas() {
    static const auto set =
        reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
    static const auto get =
        reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
    if (!set || !get) return;
    set_ = set;
    const std::lock_guard<std::mutex> lock(mutex());
    if (state().users++ == 0) state().saved = get();
    set_(1);
  }
  ~SerialBlas() {
    if (!set_) return;
    const std::lock_guard<std::mutex> lock(mutex());
    if (--state().users == 0) set_(state().saved);
  }
  SerialBlas(const SerialBlas&) = delete;
  SerialBlas& operator=(const SerialBlas&) = delete;

 private:
  struct State {
    int users = 0;
    int saved = 1;
  };
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  static State& state() {
    static State s;
    return s;
  }
  void (*set_)(int) = nullptr;
};

}  // namespace

bool run_halves(int threads, const std::function<bool(int)>& body) {
  std::array<bool, 2> ok{false, false};
  auto run = [&](int h) {
    try {
      ok[h] = body(h);
    } catch (const std::bad_alloc&) {  // (no exception may leave an OpenMP region)
      ok[h] = false;
    }
  };
  const SerialBlas serial;
  if (threads > 1) {
    // The halves' team is the last active level: CHOLMOD's regions inside it run serially.
    const ActiveLevelCap cap(1);
#pragma omp parallel for num_threads(2) schedule(static, 1)
    for (int h = 0; h < 2; ++h) run(h);
  } else {
    // No region at all: a one-thread region is not an active level, so CHOLMOD's four-thread
    // regions inside it were active and nested, and got new threads for every supernode.
    const ActiveLevelCap cap(0);
    for (int h = 0; h < 2; ++h) run(h);
  }
  return ok[0] && ok[1];
}

/// One half with the separator: M_h's lower triangle in its own numbering (the half's unknowns
/// in order, then the separator's), where each entry comes from in K, and its factor.
struct SplitCholesky::Half {
  std::vector<int> unknowns;  ///< per row of M_h: the unknown of K
  int own = 0;                ///< the half's unknowns (M_h's first rows)
  std::vector<int> start, rows;
  std::vector<Eigen::Index> source;  ///< per entry: its index in K's values
  std::vector<double> values;
  cholmod_common c{};
  cholmod_factor* factor = nullptr;
  Eigen::MatrixXd l_ss;   ///< L_SSʰ (lower triangle)
  Eigen::MatrixXd t_ss;   ///< L_SSʰ L_SSʰᵀ (lower triangle), until the Schur complement holds it

  Half() {
    cholmod_start(&c);
    c.print = 0;
    c.nmethods = 1;
    c.method[0].ordering = CHOLMOD_NATURAL;  // M_h is built in elimination order
    c.postorder = 0;                         // a postorder could move the separator's columns
    c.supernodal = CHOLMOD_SUPERNODAL;
  }
  ~Half() {
    if (factor) cholmod_free_factor(&factor, &c);
    cholmod_finish(&c);
  }
  Half(const Half&) = delete;
  Half& operator=(const Half&) = delete;

  int size() const { return static_cast<int>(unknowns.size()); }

  cholmod_sparse view() {
    return lower_view(unknowns.size(), rows.size(), start.data(), rows.data(), values.data());
  }

  /// M_h's pattern from K's lower triangle (`row` maps an unknown of K to its row of M_h, −1
  /// outside), and CHOLMOD's symbolic analysis of it.
  bool analyse(const SpMat& k, const std::vector<int>& row) {
    const int m = size();
    const int* outer = k.outerIndexPtr();
    const int* inner = k.innerIndexPtr();
    start.assign(m + 1, 0);
    auto for_each_entry = [&](auto visit) {
      for (int j : unknowns)
        for (int q = outer[j]; q < outer[j + 1]; ++q)
          if (const int i = inner[q]; i >= j && row[i] >= 0)
            visit(std::min(row[i], row[j]), std::max(row[i], row[j]), q);
    };
    for_each_entry([&](int col, int, int) { ++start[col + 1]; });
    std::partial_sum(start.begin(), start.end(), start.begin());
    rows.resize(start[m]);
    source.resize(start[m]);
    values.resize(start[m]);
    std::vector<int> next(start.begin(), start.end() - 1);
    for_each_entry([&](int col, int r, int q) {
      rows[next[col]] = r;
      source[next[col]++] = q;
    });
    sort_columns();
    if (factor) cholmod_free_factor(&factor, &c);
    cholmod_sparse a = view();
    factor = cholmod_analyze(&a, &c);
    if (!factor) return false;
    const auto* perm = static_cast<const int*>(factor->Perm);
    for (int i = 0; i < m; ++i)
      if (perm[i] != i) return false;  // the separator must stay last
    return true;
  }

  /// Rows ascending within each column (insertion sort: a column holds a few dozen entries).
  void sort_columns() {
    for (size_t j = 0; j + 1 < start.size(); ++j)
      for (int q = start[j] + 1; q < start[j + 1]; ++q)
        for (int p = q; p > start[j] && rows[p - 1] > rows[p]; --p) {
          std::swap(rows[p - 1], rows[p]);
          std::swap(source[p - 1], source[p]);
        }
  }

  /// M_h's values from K, its factorisation, L_SSʰ and L_SSʰ L_SSʰᵀ.
  bool factorize(const SpMat& k) {
    const double* x = k.valuePtr();
    for (size_t q = 0; q < values.size(); ++q) values[q] = x[source[q]];
    cholmod_sparse a = view();
    if (!cholmod_factorize(&a, factor, &c) || c.status == CHOLMOD_NOT_POSDEF ||
        factor->minor < unknowns.size())
      return false;
    VecX ones;
    if (!trailing_block(*factor, own, l_ss, ones)) return false;
    const int s = size() - own;
    t_ss = Eigen::MatrixXd::Zero(s, s);
    if (s > 0)  // (Eigen's products do not take empty operands)
      t_ss.selfadjointView<Eigen::Lower>().rankUpdate(l_ss);  // l_ss is zero above its diagonal
    return true;
  }

  /// CHOLMOD's solve of `system` (CHOLMOD_L or CHOLMOD_Lt) in place.
  bool apply(int system, Eigen::MatrixXd& z) {
    cholmod_dense b = dense_view(z);
    cholmod_dense* y = cholmod_solve(system, factor, &b, &c);
    if (!y) return false;
    z = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(y->x), z.rows(), z.cols());
    cholmod_free_dense(&y, &c);
    return true;
  }
};

struct SplitCholesky::Impl {
  int n = 0;
  std::array<Half, 2> halves;
  std::vector<int> separator;  ///< the separator's unknowns in order
  Eigen::MatrixXd schur;
  Eigen::LLT<Eigen::MatrixXd> schur_factor;
  bool analysed = false;

  int s() const { return static_cast<int>(separator.size()); }
};

SplitCholesky::SplitCholesky() : impl_(std::make_unique<Impl>()) {}
SplitCholesky::~SplitCholesky() = default;

bool SplitCholesky::analysed() const { return impl_->analysed; }
int SplitCholesky::separator_size() const { return impl_->s(); }

namespace {

/// The split's parts with every unknown of half 1 coupled to half 0 moved to the separator.
std::vector<signed char> separate_couplings(const SpMat& k, std::vector<signed char> part) {
  const int* outer = k.outerIndexPtr();
  const int* inner = k.innerIndexPtr();
  for (int j = 0; j < k.cols(); ++j)
    for (int q = outer[j]; q < outer[j + 1]; ++q) {
      const int i = inner[q];
      if (part[i] + part[j] == 1) part[part[i] == 1 ? i : j] = 2;  // one in each half
    }
  return part;
}

}  // namespace

bool SplitCholesky::analyse(const SpMat& k, const std::vector<int>& order,
                            const std::vector<signed char>& part_in, int threads) {
  Impl& m = *impl_;
  m.analysed = false;
  m.n = static_cast<int>(k.rows());
  if (!k.isCompressed() || static_cast<int>(order.size()) != m.n ||
      static_cast<int>(part_in.size()) != m.n)
    return false;
  const std::vector<signed char> part = separate_couplings(k, part_in);
  std::array<int, 3> count{0, 0, 0};
  for (signed char p : part) ++count[static_cast<size_t>(p)];
  if (count[0] == 0 || count[1] == 0 || count[2] > kMaxSeparator || 8 * count[2] > m.n)
    return false;
  // Each half's unknowns in order, then the separator's in order.
  std::array<std::vector<int>, 3> members;
  for (auto& v : members) v.clear();
  for (int q : order) members[static_cast<size_t>(part[q])].push_back(q);
  m.separator = members[2];
  for (int h = 0; h < 2; ++h) {
    Half& half = m.halves[h];
    half.own = count[h];
    half.unknowns = members[h];
    half.unknowns.insert(half.unknowns.end(), m.separator.begin(), m.separator.end());
  }
  m.analysed = run_halves(threads, [&](int h) {
    Half& half = m.halves[h];
    std::vector<int> row(m.n, -1);
    for (int r = 0; r < half.size(); ++r) row[half.unknowns[r]] = r;
    return half.analyse(k, row);
  });
  return m.analysed;
}

SolveStatus SplitCholesky::factorize(const SpMat& k, int threads) {
  Impl& m = *impl_;
  if (!m.analysed) return SolveStatus::kFailed;
  if (!run_halves(threads, [&](int h) { return m.halves[h].factorize(k); }))
    return SolveStatus::kSingular;
  // S = L_SSᴬ L_SSᴬᵀ + L_SSᴮ L_SSᴮᵀ − K_SS (lower triangles).
  const int s = m.s();
  m.schur = std::move(m.halves[0].t_ss);
  m.schur += m.halves[1].t_ss;
  m.halves[1].t_ss.resize(0, 0);
  std::vector<int> sep_row(m.n, -1);
  for (int r = 0; r < s; ++r) sep_row[m.separator[r]] = r;
  for (int r = 0; r < s; ++r)
    for (SpMat::InnerIterator it(k, m.separator[r]); it; ++it)
      if (const int i = sep_row[it.row()]; i >= r) m.schur(i, r) -= it.value();
  if (s == 0) return SolveStatus::kConverged;  // the halves are separate bodies
  m.schur_factor.compute(m.schur);
  return m.schur_factor.info() == Eigen::Success ? SolveStatus::kConverged
                                                  : SolveStatus::kSingular;
}

double SplitCholesky::pivot_ratio() const {
  const Impl& m = *impl_;
  double smallest = std::numeric_limits<double>::infinity(), largest = 0;
  for (const Half& half : m.halves) {
    double lo = 0, hi = 0;
    diagonal_range(*half.factor, half.own, lo, hi);
    smallest = std::min(smallest, lo);
    largest = std::max(largest, hi);
  }
  if (m.s() > 0) {
    const VecX d = m.schur_factor.matrixLLT().diagonal().cwiseAbs();
    smallest = std::min(smallest, d.minCoeff());
    largest = std::max(largest, d.maxCoeff());
  }
  return largest > 0 && std::isfinite(smallest) ? std::pow(smallest / largest, 2) : 0.0;
}

double SplitCholesky::factor_nonzeros() const {
  const Impl& m = *impl_;
  const double s = m.s();
  return m.halves[0].c.lnz + m.halves[1].c.lnz + s * (s + 1) / 2;
}

SolveStatus SplitCholesky::solve(const Eigen::MatrixXd& b, Eigen::MatrixXd& x, int threads) {
  Impl& m = *impl_;
  const int s = m.s();
  const Eigen::Index cols = b.cols();
  std::array<Eigen::MatrixXd, 2> w;
  // Forward: L_h wʰ = [b_h; 0].
  const bool forward = run_halves(threads, [&](int h) {
    Half& half = m.halves[h];
    w[h] = Eigen::MatrixXd::Zero(half.size(), cols);
    for (int r = 0; r < half.own; ++r) w[h].row(r) = b.row(half.unknowns[r]);
    return half.apply(CHOLMOD_L, w[h]);
  });
  if (!forward) return SolveStatus::kFailed;
  // The separator: S x_S = b_S + Σ_h L_SSʰ w_Sʰ.
  Eigen::MatrixXd x_s(s, cols);
  for (int r = 0; r < s; ++r) x_s.row(r) = b.row(m.separator[r]);
  if (s > 0) {
    for (int h = 0; h < 2; ++h)
      x_s.noalias() += m.halves[h].l_ss.triangularView<Eigen::Lower>() * w[h].bottomRows(s);
    x_s = m.schur_factor.solve(x_s);
  }
  // Backward: L_hᵀ y = [w_hʰ; L_SSʰᵀ x_S], y_h = x_h.
  x.resize(b.rows(), cols);
  const bool backward = run_halves(threads, [&](int h) {
    Half& half = m.halves[h];
    if (s > 0)
      w[h].bottomRows(s).noalias() = half.l_ss.triangularView<Eigen::Lower>().transpose() * x_s;
    if (!half.apply(CHOLMOD_Lt, w[h])) return false;
    for (int r = 0; r < half.own; ++r) x.row(half.unknowns[r]) = w[h].row(r);
    return true;
  });
  for (int r = 0; r < s; ++r) x.row(m.separator[r]) = x_s.row(r);
  return backward ? SolveStatus::kConverged : SolveStatus::kFailed;
}

}  // namespace c2d::core
