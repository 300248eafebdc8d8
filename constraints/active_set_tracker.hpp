// The one cycle detector of the set iterations (issue 33, item 3): what entered, what left, and
// whether a set has come back (cycling, which CalculiX and code_aster also detect) instead of
// looping to the iteration limit. Every loop that updates sets records them here: the active-set
// loops of the multiplier methods, the penalised solver, the frictional set iteration (whose
// sets hold normal and tangential states and law pieces) and a load step's outer iterations.
#pragma once

#include <set>
#include <vector>

namespace c2d::constraints {

class ActiveSetTracker {
 public:
  /// Entries are states (0 open or free; a frictional set's stick/slip codes and law pieces):
  /// entering and leaving count entries turning nonzero and zero, `unchanged` compares all.
  struct Change {
    int entering = 0, leaving = 0;
    bool unchanged = false;  ///< same as the previous set: converged
    bool repeated = false;   ///< equal to an earlier, not the previous, set: cycling
  };
  /// Records the next active set and compares it with the ones seen so far.
  Change record(const std::vector<char>& active);
  /// Takes `set` as the last set without remembering it as seen: a set that may legitimately
  /// come back (a load step's predictor, solved at another state).
  void follow(const std::vector<char>& set);
  /// Forgets every set and starts again from `set` (a loop that changed its rule or its start).
  void restart(const std::vector<char>& set);
  void reset();

 private:
  std::vector<char> last_;
  bool has_last_ = false;
  std::set<std::vector<char>> seen_;
};

/// Number of set entries.
int count_active(const std::vector<char>& active);

}  // namespace c2d::constraints
