#include "constraints/active_set_tracker.hpp"

#include <algorithm>

namespace c2d::constraints {

ActiveSetTracker::Change ActiveSetTracker::record(const std::vector<char>& active) {
  Change c;
  if (has_last_) {
    for (size_t i = 0; i < active.size(); ++i) {
      c.entering += active[i] && !last_[i];
      c.leaving += !active[i] && last_[i];
    }
    // (entries may be states, not flags: a stick row turning to slip changes the set)
    c.unchanged = active == last_;
    c.repeated = !c.unchanged && seen_.count(active) > 0;
  } else {
    c.entering = count_active(active);
  }
  seen_.insert(active);
  last_ = active;
  has_last_ = true;
  return c;
}

void ActiveSetTracker::follow(const std::vector<char>& set) {
  last_ = set;
  has_last_ = true;
}

void ActiveSetTracker::restart(const std::vector<char>& set) {
  reset();
  record(set);
}

void ActiveSetTracker::reset() {
  last_.clear();
  has_last_ = false;
  seen_.clear();
}

int count_active(const std::vector<char>& active) {
  return static_cast<int>(std::count(active.begin(), active.end(), 1));
}

}  // namespace c2d::constraints
