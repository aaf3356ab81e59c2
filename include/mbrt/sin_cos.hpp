// sin and cos of one angle, inline and with a fixed instruction count: the
// staggered-tree step takes one per revolute joint per step, where a call
// into the C library costs more than the rest of the joint's recursion.
// Cody & Waite's reduction (1980, "Software Manual for the Elementary
// Functions", ch. 8): x = k pi/2 + r with pi/2 split into parts whose
// products with k are exact for |k| < 2^20 (|x| < 1.6e6 rad), then the
// Taylor series on |r| <= pi/4, through r^17 for sin and r^16 for cos: the
// first terms left out, below 1e-19 and 2e-18, are under 1/50 ulp.
#pragma once

#include <cmath>

#include "mbrt/mul_add.hpp"

namespace mbrt {

struct SinCos {
  double c, s;
};

// a x^n + b x^(n-1) + ... by Horner's rule, written out by the compiler as
// one chain of multiply-adds (a loop over the coefficients was not unrolled).
inline double horner(double, double a) noexcept { return a; }
template <class... Rest>
inline double horner(double x, double a, double b, Rest... rest) noexcept {
  return horner(x, mul_add(a, x, b), rest...);
}

inline SinCos sin_cos(double x) noexcept {
  constexpr double kTwoOverPi = 0.6366197723675814;
  constexpr double kHalfPi1 = 1.5707963267341256;      // 33 bits
  constexpr double kHalfPi2 = 6.077100506303966e-11;   // the next 33
  constexpr double kHalfPi3 = 2.0222662487959506e-21;  // the rest
  const double k = std::nearbyint(x * kTwoOverPi);
  const double r = ((x - k * kHalfPi1) - k * kHalfPi2) - k * kHalfPi3;
  const double r2 = r * r;
  // (-1)^n / (2n + 1)!, n = 8 down to 1, and (-1)^n / (2n)!, n = 8 down to 2.
  const double ps = horner(r2, 2.8114572543455206e-15, -7.647163731819816e-13, 1.6059043836821613e-10,
                           -2.505210838544172e-08, 2.7557319223985893e-06, -0.0001984126984126984,
                           0.008333333333333333, -0.16666666666666666);
  const double pc = horner(r2, 4.779477332387385e-14, -1.1470745597729725e-11, 2.08767569878681e-09,
                           -2.755731922398589e-07, 2.48015873015873e-05, -0.001388888888888889,
                           0.041666666666666664);
  const double s = mul_add(r * r2, ps, r);
  const double c = mul_add(r2 * r2, pc, mul_add(-0.5, r2, 1.0));
  switch (static_cast<long>(k) & 3) {
    case 0: return {c, s};
    case 1: return {-s, c};
    case 2: return {-c, -s};
    default: return {s, -c};
  }
}

}  // namespace mbrt
