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

// c0 + c1 t + ... + c(N-1) t^(N-1) + the harmonic terms.
template <size_t N, size_t H>
inline TimeValue polynomial_and_harmonics(const std::array<double, N>& c, const std::array<Harmonic, H>& terms,
                                          double t) noexcept {
  TimeValue v = polynomial(c.data(), N, t);
  for (const Harmonic& h : terms) {
    const TimeValue s = sine({h.amplitude, h.omega, h.phase, 0.0}, t);
    v.f += s.f;
    v.df += s.df;
    v.ddf += s.ddf;
  }
  return v;
}

}  // namespace mbrt
