// Result of one step. The step never throws; a bad step leaves the last good
// state in place and says why.
#pragma once

namespace mbrt {

enum class StepStatus : int {
  ok = 0,
  non_finite = 1,      // a NaN or Inf appeared; the state was restored
  not_positive = 2,    // the constraint matrix lost positive definiteness; the state was restored
};

inline const char* to_string(StepStatus s) noexcept {
  switch (s) {
    case StepStatus::ok: return "ok";
    case StepStatus::non_finite: return "non_finite";
    case StepStatus::not_positive: return "not_positive";
  }
  return "unknown";
}

}  // namespace mbrt
