// Wall-clock laps for the per-phase times every solver reports.
#pragma once

#include <chrono>

namespace c2d::core {

class Stopwatch {
 public:
  /// Seconds since construction or the previous lap; starts the next lap.
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - start_).count();
    start_ = now;
    return s;
  }
  /// Seconds since construction or the previous lap, without starting a new one.
  double elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace c2d::core
