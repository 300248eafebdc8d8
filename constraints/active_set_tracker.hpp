// Active-set bookkeeping shared by the iterative backends: what entered, what left, and whether
// a set has come back (cycling, which CalculiX and code_aster also detect) instead of looping to
// the iteration limit.
#pragma once

#include <set>
#include <vector>

namespace c2d::constraints {

class ActiveSetTracker {
 public:
  struct Change {
    int entering = 0, leaving = 0;
    bool unchanged = false;  ///< same as the previous set: converged
    bool repeated = false;   ///< equal to an earlier, not the previous, set: cycling
  };
  /// Records the next active set and compares it with the ones seen so far.
  Change record(const std::vector<char>& active);
  void reset();

 private:
  std::vector<char> last_;
  bool has_last_ = false;
  std::set<std::vector<char>> seen_;
};

/// Number of set entries.
int count_active(const std::vector<char>& active);

}  // namespace c2d::constraints
