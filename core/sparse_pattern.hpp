// The pattern a sparse factorisation was analysed for, kept to decide whether the next matrix
// may reuse that analysis. Compared in full: a matrix with as many non-zeros in other places
// (a regularising row moved to another node) needs its own analysis, which a check of size and
// count alone would not see (the factor would be wrong, silently).
#pragma once

#include <algorithm>
#include <vector>

#include "core/types.hpp"

namespace c2d::core {

class AnalysedPattern {
 public:
  /// Whether K (compressed) has the kept pattern.
  bool matches(const SpMat& k) const {
    return k.isCompressed() && !start_.empty() &&
           start_.size() == static_cast<size_t>(k.outerSize() + 1) &&
           index_.size() == static_cast<size_t>(k.nonZeros()) &&
           std::equal(start_.begin(), start_.end(), k.outerIndexPtr()) &&
           std::equal(index_.begin(), index_.end(), k.innerIndexPtr());
  }
  /// Keeps K's pattern (nothing when K is not compressed: it then matches nothing).
  void keep(const SpMat& k) {
    clear();
    if (!k.isCompressed()) return;
    start_.assign(k.outerIndexPtr(), k.outerIndexPtr() + k.outerSize() + 1);
    index_.assign(k.innerIndexPtr(), k.innerIndexPtr() + k.nonZeros());
  }
  void clear() {
    start_.clear();
    index_.clear();
  }

 private:
  std::vector<int> start_, index_;
};

}  // namespace c2d::core
