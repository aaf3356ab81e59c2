// a * b + c, in one instruction where the CPU has fused multiply-add: the
// generated straight-line recursions (docs/staggered-tree.md) are mostly
// such terms.
#pragma once

#include <cmath>

namespace mbrt {

inline double mul_add(double a, double b, double c) noexcept {
#ifdef __FMA__
  return std::fma(a, b, c);
#else
  return a * b + c;
#endif
}

}  // namespace mbrt
