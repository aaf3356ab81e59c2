// Prescribed functions of time for drivers (rheonomic constraints), with
// their first and second derivatives.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

namespace mbrt {

struct TimeValue {
  double f;
  double df;
  double ddf;
};

// f(t) = c[0] + c[1] t + ... + c[n-1] t^(n-1), by Horner's rule.
inline TimeValue polynomial(const double* c, size_t n, double t) noexcept {
  TimeValue v{0.0, 0.0, 0.0};
  for (size_t k = n; k-- > 0;) {
    v.ddf = v.ddf * t + 2.0 * v.df;
    v.df = v.df * t + v.f;
    v.f = v.f * t + c[k];
  }
  return v;
}

template <size_t N>
inline TimeValue polynomial(const std::array<double, N>& c, double t) noexcept {
  return polynomial(c.data(), N, t);
}

// f(t) = offset + amplitude sin(omega t + phase).
struct Sine {
  double amplitude, omega, phase, offset;
};

inline TimeValue sine(const Sine& s, double t) noexcept {
  const double x = s.omega * t + s.phase;
  const double a = s.amplitude * std::sin(x);
  return {s.offset + a, s.amplitude * s.omega * std::cos(x), -s.omega * s.omega * a};
}

}  // namespace mbrt
