// Outcome of a numerical solve: failure is data, never an exception.
#pragma once

#include <string>

namespace c2d {

enum class SolveStatus {
  kConverged,
  kMaxIterations,
  kDiverged,
  kCycling,
  kSingular,
  kIllConditioned,
  kFailed,
};

/// Stable lower-case names used in summary.json and tables.
const char* to_string(SolveStatus s);

}  // namespace c2d
