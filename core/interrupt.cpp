#include "core/interrupt.hpp"

#include <chrono>
#include <utility>

namespace c2d::core {

namespace {

thread_local InterruptPoll* t_poll = nullptr;

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

InterruptPoll::InterruptPoll(std::function<bool()> poll) : poll_(std::move(poll)), outer_(t_poll) {
  t_poll = this;
}

InterruptPoll::~InterruptPoll() { t_poll = outer_; }

bool interrupt_requested() {
  InterruptPoll* p = t_poll;
  if (!p) return false;
  if (p->requested_) return true;
  const double now = now_seconds();
  if (p->last_ >= 0 && now - p->last_ < 0.05) return false;
  p->last_ = now;
  try {
    p->requested_ = p->poll_ && p->poll_();
  } catch (...) {
    p->requested_ = true;  // a poll that fails cannot let the run go on unasked
  }
  return p->requested_;
}

void check_interrupt() {
  if (interrupt_requested()) throw Interrupted();
}

}  // namespace c2d::core
