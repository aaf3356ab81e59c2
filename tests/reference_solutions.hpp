// Independent reference solutions shared by tests and timing/: none of them
// uses mbrt's code.
#pragma once

#include <cmath>
#include <vector>

#include <mbrt/types.hpp>

namespace reference {

// One classical RK4 step of the one-coordinate equation q'' = acc(q).
template <class Acceleration>
inline void rk4_step(double& q, double& rate, double h, Acceleration acc) {
  const double k1p = rate, k1v = acc(q);
  const double k2p = rate + 0.5 * h * k1v, k2v = acc(q + 0.5 * h * k1p);
  const double k3p = rate + 0.5 * h * k2v, k3v = acc(q + 0.5 * h * k2p);
  const double k4p = rate + h * k3v, k4v = acc(q + h * k3p);
  q += h / 6.0 * (k1p + 2 * k2p + 2 * k3p + k4p);
  rate += h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
}

// A01 pendulum (1 kg on a 1 m massless bar from the horizontal, g = 9.81):
// the bob position at t = 0, dt, 2 dt, ... up to t_end, from the minimal-
// coordinate equation phi'' = -g cos(phi), phi(0) = pi, by classical RK4 at
// step h. Reproduces the published A01 table to its 6 digits at h <= 5e-4.
inline std::vector<mbrt::Vec3> a01_bob_positions(double t_end, double dt, double h) {
  const auto acc = [](double a) { return -9.81 * std::cos(a); };
  double phi = M_PI, rate = 0.0;
  std::vector<mbrt::Vec3> out{{std::cos(phi), std::sin(phi), 0.0}};
  const long per_sample = std::lround(dt / h);
  const long samples = std::lround(t_end / dt);
  for (long s = 0; s < samples; ++s) {
    for (long i = 0; i < per_sample; ++i) rk4_step(phi, rate, h, acc);
    out.emplace_back(std::cos(phi), std::sin(phi), 0.0);
  }
  return out;
}

struct TimedValue {
  double t, value;
};

// Heavy top benchmark (m = 15, J = diag(0.234375, 0.46875, 0.234375), COM
// 1 m from the fixed point, spin 150 rad/s): height of the centre of mass
// from u'^2 = f(u) of the Lagrange top, which is integrable (nutation period
// 0.7452069476 s). Agrees with the published RK4 Euler parameters to their
// 5 digits at t = 0.2 and 2.
inline constexpr TimedValue kHeavyTopHeight[] = {
    {0.05, -0.038355180}, {0.1, -0.149164701}, {0.2, -0.523983027}, {0.3, -0.897531991},
    {0.5, -0.711400258},  {1.0, -0.748490791}, {1.5, -0.001422084}, {2.0, -0.673022270}};

}  // namespace reference
