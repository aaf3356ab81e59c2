// Independent reference solutions shared by tests and timing/: none of them
// uses mbrt's code.
#pragma once

#include <cmath>
#include <type_traits>
#include <vector>

#include <Eigen/Dense>

#include <mbrt/types.hpp>

namespace reference {

// One classical RK4 step of q'' = acc(q, q'), q a double or an Eigen vector.
// acc may also take q alone (no velocity dependence).
template <class Q, class Acceleration>
inline void rk4_step(Q& q, Q& rate, double h, Acceleration acc) {
  const auto a = [&acc](const Q& x, const Q& v) -> Q {
    if constexpr (std::is_invocable_v<Acceleration, const Q&, const Q&>) {
      return acc(x, v);
    } else {
      return acc(x);
    }
  };
  const Q k1p = rate, k1v = a(q, k1p);
  const Q k2p = rate + 0.5 * h * k1v, k2v = a(q + 0.5 * h * k1p, k2p);
  const Q k3p = rate + 0.5 * h * k2v, k3v = a(q + 0.5 * h * k2p, k3p);
  const Q k4p = rate + h * k3v, k4v = a(q + h * k3p, k4p);
  q += h / 6.0 * (k1p + 2 * k2p + 2 * k3p + k4p);
  rate += h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
}

// Integrates q'' = acc(q, q') from (q0, rate0) by classical RK4 at step h
// and returns observe(q) at t = 0, dt, 2 dt, ... up to t_end.
template <class Q, class Acceleration, class Observe>
inline std::vector<mbrt::Vec3> sampled_rk4(Q q, Q rate, Acceleration acc, Observe observe, double t_end, double dt,
                                           double h) {
  std::vector<mbrt::Vec3> out{observe(q)};
  const long per_sample = std::lround(dt / h);
  const long samples = std::lround(t_end / dt);
  for (long s = 0; s < samples; ++s) {
    for (long i = 0; i < per_sample; ++i) rk4_step(q, rate, h, acc);
    out.push_back(observe(q));
  }
  return out;
}

// A01 pendulum (1 kg on a 1 m massless bar from the horizontal, g = 9.81):
// the bob position at t = 0, dt, 2 dt, ... up to t_end, from the minimal-
// coordinate equation phi'' = -g cos(phi), phi(0) = pi, by classical RK4 at
// step h. Reproduces the published A01 table to its 6 digits at h <= 5e-4.
inline std::vector<mbrt::Vec3> a01_bob_positions(double t_end, double dt, double h) {
  const auto acc = [](double a) { return -9.81 * std::cos(a); };
  const auto bob = [](double phi) { return mbrt::Vec3(std::cos(phi), std::sin(phi), 0.0); };
  return sampled_rk4(M_PI, 0.0, acc, bob, t_end, dt, h);
}

// A02 N four-bar (N windows of uniform 1 kg, 1 m rods; tools/make_n_four_bar.py):
// with every crank parallel to the first and every coupler translating, the
// crank angle theta from +x obeys theta'' = -k g cos(theta), k = 3 (3N + 1) /
// (2 (4N + 1)), theta(0) = pi/2, theta'(0) = -1. Returns B0, the top of the
// first crank, at t = 0, dt, 2 dt, ... up to t_end, by classical RK4 at step h.
inline std::vector<mbrt::Vec3> a02_b0_positions(int n, double t_end, double dt, double h) {
  const double k = 3.0 * (3 * n + 1) / (2.0 * (4 * n + 1));
  const auto acc = [k](double a) { return -k * 9.81 * std::cos(a); };
  const auto b0 = [](double th) { return mbrt::Vec3(std::cos(th), std::sin(th), 0.0); };
  return sampled_rk4(M_PI / 2, -1.0, acc, b0, t_end, dt, h);
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

// Planar chain of n uniform rods (mass 1 kg, length 1 m, in-plane inertia
// 1/12 kg m^2 about the centre; tools/make_chain.py), pinned at the origin,
// released from rest along +x, gravity 9.81 in -y. Lagrange's equations in
// the absolute link angles th (from +x), with a_ij the lever of link j's angle
// on link i's centre (1 for j < i, 1/2 for j = i) and C_jk = sum_i a_ij a_ik:
//   sum_k (C_jk cos(th_j - th_k) + I d_jk) th_k'' + sum_k C_jk sin(th_j - th_k) th_k'^2
//     + g b_j cos(th_j) = 0,   b_j = sum_i a_ij.
// Returns the tip of the last link at t = 0, dt, 2 dt, ... up to t_end, by
// classical RK4 at step h.
inline std::vector<mbrt::Vec3> chain_tip_positions(int n, double t_end, double dt, double h) {
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j <= i; ++j) {
      const double aij = j < i ? 1.0 : 0.5;
      b(j) += aij;
      for (int k = 0; k <= i; ++k) c(j, k) += aij * (k < i ? 1.0 : 0.5);
    }
  }
  const auto acc = [&](const Eigen::VectorXd& th, const Eigen::VectorXd& rate) -> Eigen::VectorXd {
    Eigen::MatrixXd mass(n, n);
    Eigen::VectorXd rhs(n);
    for (int j = 0; j < n; ++j) {
      rhs(j) = -9.81 * b(j) * std::cos(th(j));
      for (int k = 0; k < n; ++k) {
        mass(j, k) = c(j, k) * std::cos(th(j) - th(k)) + (j == k ? 1.0 / 12.0 : 0.0);
        rhs(j) -= c(j, k) * std::sin(th(j) - th(k)) * rate(k) * rate(k);
      }
    }
    return mass.llt().solve(rhs);
  };
  const auto tip = [n](const Eigen::VectorXd& th) {
    mbrt::Vec3 p = mbrt::Vec3::Zero();
    for (int j = 0; j < n; ++j) p += mbrt::Vec3(std::cos(th(j)), std::sin(th(j)), 0.0);
    return p;
  };
  const Eigen::VectorXd rest = Eigen::VectorXd::Zero(n);
  return sampled_rk4(rest, rest, acc, tip, t_end, dt, h);
}

// Andrews' squeezer (Test Set for IVP Solvers, problem "andrews"): the crank
// angle beta at t = 0.03 s of the Test Set's reference solution (deTestSet
// `andsoln`, PSIDE at rtol = atol = 1e-14; also in test_benchmark_andrews.cpp)
// and the crank's length rr, from O to its joint F at rr (cos beta, sin beta).
inline constexpr double kAndrewsTime = 0.03;
inline constexpr double kAndrewsCrankAngle = 0.1581077119629904e+2;
inline constexpr double kAndrewsCrankLength = 0.007;

// The centre of mass of the last link of tests/models/stress/arm_7.yaml and of
// spatial_chain_16_revolute.yaml after 0.5 s,
// from Simbody 3.7's error-controlled Runge-Kutta-Merson at accuracy 1e-12 on
// the same model files (timing/tree_reference; within 9e-12 m of the same at
// accuracy 1e-10 and 1.5e-13 m of MuJoCo 2.2.2's RK4 at h = 1e-6 s).
inline const mbrt::Vec3 kArmTipAtHalfSecond(0.29273643659973658, 1.1484086788439551, -0.29510903100918962);
inline const mbrt::Vec3 kChainTipAtHalfSecond(2.3136093813900782, 1.7293991660643162, -2.1970150626112317);

}  // namespace reference
