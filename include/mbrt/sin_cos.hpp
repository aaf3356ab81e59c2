// sin and cos of one angle, inline and with a fixed instruction count: the
// staggered-tree step takes one per revolute joint per step, where a call
// into the C library costs more than the rest of the joint's recursion.
// Cody & Waite's reduction (1980, "Software Manual for the Elementary
// Functions", ch. 8): x = k pi/2 + r with pi/2 split into parts whose
// products with k are exact for |k| < 2^20 (|x| < 1.6e6 rad), then on
// |r| <= pi/4 the polynomials of least weighted maximum error (Remez's
// exchange algorithm; Cheney 1966, "Introduction to Approximation Theory",
// ch. 3) in z = r^2: sin r = r + r^3 P(z), P of degree 5 (relative error
// below 6e-18), and cos r = 1 - z/2 + z^2 Q(z), Q of degree 4 (error below
// 8e-17), the forms of Sun's fdlibm kernels (k_sin.c, k_cos.c). The
// coefficients were fitted in 60-digit arithmetic and rounded to double;
// the bounds hold with the rounded coefficients.
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
  const double ps = horner(r2, 1.5896827930152048e-10, -2.505075865328765e-08, 2.7557313695226595e-06,
                           -0.0001984126982981695, 0.008333333333322425, -0.16666666666666632);
  const double pc = horner(r2, 2.0647738026849684e-09, -2.7555567133567866e-07, 2.4801580971686814e-05,
                           -0.0013888888878274372, 0.04166666666660226);
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
