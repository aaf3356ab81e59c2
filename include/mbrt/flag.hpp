// 1.0 where a condition holds, else 0.0, made from the condition's bit
// rather than selected. The step multiplies by such flags (a stuck joint, a
// touching contact) so that its work does not depend on the state: the
// instruction-count tests check that every step executes the same
// instructions. Written as static_cast<double>(b), the compiler may turn the
// flag into a branch where it sees that the value is 0 or 1, and then it
// did, depending on how it inlined the models of one translation unit.
#pragma once

#include <cstdint>
#include <cstring>

namespace mbrt {

inline double flag(bool b) noexcept {
  const double one = 1.0;
  std::uint64_t bits = 0;
  std::memcpy(&bits, &one, sizeof bits);
  bits &= std::uint64_t{0} - static_cast<std::uint64_t>(b);  // all ones or all zeros
  double out = 0.0;
  std::memcpy(&out, &bits, sizeof out);
  return out;
}

}  // namespace mbrt
