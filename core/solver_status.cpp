#include "core/solver_status.hpp"

namespace c2d {

const char* to_string(SolveStatus s) {
  switch (s) {
    case SolveStatus::kConverged: return "converged";
    case SolveStatus::kMaxIterations: return "max_iterations";
    case SolveStatus::kDiverged: return "diverged";
    case SolveStatus::kCycling: return "cycling";
    case SolveStatus::kSingular: return "singular";
    case SolveStatus::kIllConditioned: return "ill_conditioned";
    case SolveStatus::kPenetration: return "penetration";
    case SolveStatus::kInvertedElement: return "inverted_element";
    case SolveStatus::kStalled: return "stalled";
    case SolveStatus::kFailed: return "failed";
  }
  return "failed";
}

}  // namespace c2d
