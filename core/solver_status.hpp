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
  /// The final state penetrates more than the method reports (checked on fresh detection).
  kPenetration,
  /// An element turned inside out (J ≤ 0): a load step too large, or a bad mesh.
  kInvertedElement,
  /// No progress: Newton could not move (a zero step above the tolerance), or load stepping
  /// reached its bound on attempts.
  kStalled,
  kFailed,
};

/// Stable lower-case names used in summary.json and tables.
const char* to_string(SolveStatus s);

}  // namespace c2d
