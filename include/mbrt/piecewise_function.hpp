// Pieces of a piecewise function of time for drivers: a polynomial plus
// harmonic terms, with exact first and second derivatives. The generated
// code picks the piece by time and calls this for it.
#pragma once

#include <array>
#include <cstddef>

#include "mbrt/time_functions.hpp"

namespace mbrt {

// amplitude sin(omega t + phase); a cosine is phase pi/2.
struct Harmonic {
  double amplitude, omega, phase;
};

// c0 + c1 t + ... + c(n-1) t^(n-1) + the m harmonic terms.
inline TimeValue polynomial_and_harmonics(const double* c, size_t n, const Harmonic* terms, size_t m,
                                          double t) noexcept {
  TimeValue v = polynomial(c, n, t);
  for (size_t k = 0; k < m; ++k) {
    const TimeValue s = sine({terms[k].amplitude, terms[k].omega, terms[k].phase, 0.0}, t);
    v.f += s.f;
    v.df += s.df;
    v.ddf += s.ddf;
  }
  return v;
}

template <size_t N, size_t H>
inline TimeValue polynomial_and_harmonics(const std::array<double, N>& c, const std::array<Harmonic, H>& terms,
                                          double t) noexcept {
  return polynomial_and_harmonics(c.data(), N, terms.data(), H, t);
}

}  // namespace mbrt
