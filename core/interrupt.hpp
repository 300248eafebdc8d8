// Interruption of a long solve by its caller, without signals: the caller (the Python module,
// an embedding program) installs a poll on its thread for the duration of a call; the library
// asks it at checkpoints (phases, load steps, Newton and active-set iterations) and unwinds with
// Interrupted when it answers yes. The library itself never touches signal dispositions.
#pragma once

#include <functional>
#include <stdexcept>

namespace c2d::core {

/// Thrown from a checkpoint once the caller's poll asked to stop. Not an InputError and not a
/// solver status: the run is abandoned, its work folder removed by the objects that own it.
class Interrupted : public std::runtime_error {
 public:
  Interrupted() : std::runtime_error("interrupted by the caller") {}
};

/// The poll in force on this thread while the object lives (nested polls: the innermost). The
/// poll is called at most every 50 ms; once it returns true, every later checkpoint throws.
class InterruptPoll {
 public:
  explicit InterruptPoll(std::function<bool()> poll);
  ~InterruptPoll();
  InterruptPoll(const InterruptPoll&) = delete;
  InterruptPoll& operator=(const InterruptPoll&) = delete;

 private:
  std::function<bool()> poll_;
  InterruptPoll* outer_;
  double last_ = -1.0;
  bool requested_ = false;
  friend bool interrupt_requested();
};

/// Asks this thread's poll (if any, and if 50 ms have passed since it was last asked); true once
/// the caller asked to stop. Never throws; for C callbacks that must return a flag.
bool interrupt_requested();

/// Throws Interrupted when interrupt_requested().
void check_interrupt();

}  // namespace c2d::core
