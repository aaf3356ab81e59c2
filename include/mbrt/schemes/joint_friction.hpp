// Coulomb friction in the joints of a tree (docs/friction.md), as a
// velocity-level impulse after the step without it: Moreau's sweeping
// process (Moreau 1988, "Unilateral contact and dry friction in finite
// freedom dynamics", in Nonsmooth Mechanics and Applications, CISM 302) as
// time-stepping methods take it (Stewart 2000, "Rigid-body dynamics with
// friction and impact", SIAM Review 42(1)). Over a step of length h the
// friction impulses p_i of the friction joints satisfy the principle of
// maximal dissipation:
//   qd+ = qd_free + M(q)^-1 P p,   |p_i| <= T_i h,
//   p_i = -T_i h sign(qd+_i) where qd+_i != 0 (slip), qd+_i = 0 where |p_i| < T_i h (stick),
// P placing the joints' impulses among the joint coordinates, T_i the
// static limit for a joint at rest at the step's start and the kinetic one
// otherwise, each a constant plus a multiple of the joint's transverse
// reaction. With the joints' block G of M^-1 (positive definite), each p_i
// in turn is the clamped value that zeroes its own end-of-step rate:
// projected Gauss-Seidel, a fixed count of sweeps, warm-started from the
// last step's impulses, then one exact solve on the stuck joints. The
// positions take the impulse as a force p / h constant over the step,
// h^2/2 M^-1 P p / h, and a joint stuck through the whole step is put back
// where it started.
//
// M provides kFrictionJoints, kFrictionDof, kFrictionLimit (kinetic),
// kFrictionStaticLimit, kFrictionPerLoad, kFrictionStaticPerLoad (limits per
// newton of transverse reaction), kFrictionLoads and, where it is true,
// friction_loads (the transverse reactions at the state), kFrictionSweeps
// and friction_response (the columns M^-1 P, the articulated-body recursion
// of Featherstone 2008, "Rigid Body Dynamics Algorithms", table 7.1, with a
// unit force in one joint and nothing else); State has friction and stuck;
// Workspace has friction_columns and q0 (the step's start).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <type_traits>

#include <Eigen/Core>

#include "mbrt/dense_cholesky.hpp"

namespace mbrt::schemes {

// A model's joints with friction: M::kFrictionJoints, or none where the
// model declares none.
template <class M, class = void>
inline constexpr int kFrictionJointsOf = 0;
template <class M>
inline constexpr int kFrictionJointsOf<M, std::void_t<decltype(M::kFrictionJoints)>> = M::kFrictionJoints;

// x with x_i = 0 where mask_i = 0 and sum_k G_ik x_k = b_i where mask_i = 1,
// G_ik = g[k][dof_i] the friction joints' block of M^-1 (positive
// definite): the masked rows are made identity, so the work is one n x n
// Cholesky factorization whatever the mask.
template <class M, std::size_t n = M::kFrictionJoints>
std::array<double, n> solve_friction_block(const typename M::FrictionColumns& g, const std::array<double, n>& mask,
                                           const std::array<double, n>& b) noexcept {
  constexpr int nn = static_cast<int>(n);
  Eigen::Matrix<double, nn, nn> a;
  Eigen::Matrix<double, nn, 1> x;
  for (int i = 0; i < nn; ++i) {
    const std::size_t ui = static_cast<std::size_t>(i);
    for (int k = 0; k < nn; ++k) {
      const std::size_t uk = static_cast<std::size_t>(k);
      a(i, k) = mask[ui] * mask[uk] * g[uk][M::kFrictionDof[ui]] + (i == k ? 1.0 - mask[ui] : 0.0);
    }
    x(i) = mask[ui] * b[ui];
  }
  mbrt::cholesky_in_place(a);
  mbrt::solve_lower(a, x);
  mbrt::solve_lower_transposed(a, x);
  std::array<double, n> out;
  for (std::size_t i = 0; i < n; ++i) out[i] = x(static_cast<int>(i));
  return out;
}

// (s.q, s.qd without friction, w.half_angles of s.q, w.q0 the step's start)
// => (s.q, s.qd with the friction impulses, s.friction, s.stuck,
// w.half_angles). Fixed work whatever the joints do; allocates nothing.
template <class M>
void joint_friction(typename M::State& s, typename M::Workspace& w) noexcept {
  constexpr std::size_t n = M::kFrictionJoints;
  constexpr double h = M::kStep;
  auto& g = w.friction_columns;
  M::friction_response(s, w.half_angles, g);
  const auto rate = [&](std::size_t i, const std::array<double, n>& impulse) {  // joint i's end rate
    double v = s.qd[M::kFrictionDof[i]];
    for (std::size_t k = 0; k < n; ++k) v += g[k][M::kFrictionDof[i]] * impulse[k];
    return v;
  };
  std::array<double, n> load{};  // transverse reactions, where limits depend on them
  if constexpr (M::kFrictionLoads) {
    // At the frictionless step's end: a splitting, like the impulses.
    M::body_states(s.q, w.half_angles, s.qd, s);
    M::friction_loads(s, load);
  }
  std::array<double, n> p, v, limit;  // impulses, their joints' rates, |p| bounds
  for (std::size_t i = 0; i < n; ++i) {
    // A joint at rest at the step's start (stuck, or started at rest) holds
    // up to its static limit; a sliding one feels the kinetic limit.
    const bool at_rest = s.stuck[i] == 1.0 || w.qd0[M::kFrictionDof[i]] == 0.0;
    limit[i] = (at_rest ? M::kFrictionStaticLimit[i] + M::kFrictionStaticPerLoad[i] * load[i]
                        : M::kFrictionLimit[i] + M::kFrictionPerLoad[i] * load[i]) *
               h;
    p[i] = std::fmin(std::fmax(s.friction[i] * h, -limit[i]), limit[i]);  // fmax drops a NaN of a failed step
  }
  for (std::size_t i = 0; i < n; ++i) v[i] = rate(i, p);
  for (int sweep = 0; sweep < M::kFrictionSweeps; ++sweep) {
    for (std::size_t i = 0; i < n; ++i) {
      const double next = std::fmin(std::fmax(p[i] - v[i] / g[i][M::kFrictionDof[i]], -limit[i]), limit[i]);
      const double change = next - p[i];
      p[i] = next;
      for (std::size_t k = 0; k < n; ++k) v[k] += g[i][M::kFrictionDof[k]] * change;
    }
  }
  // The sweeps converge slowly where joints are strongly coupled; with the
  // stick/slip split they found, one exact solve on the stuck joints (slipping
  // ones at their limits) stops them to round-off, then the bounds again.
  std::array<double, n> stuck, minus_rate;
  for (std::size_t i = 0; i < n; ++i) {
    stuck[i] = std::abs(p[i]) < limit[i] ? 1.0 : 0.0;
    minus_rate[i] = -rate(i, p);
  }
  const std::array<double, n> to_stop = solve_friction_block<M>(g, stuck, minus_rate);
  for (std::size_t i = 0; i < n; ++i) {
    p[i] = std::fmin(std::fmax(p[i] + to_stop[i], -limit[i]), limit[i]);
    stuck[i] = std::abs(p[i]) < limit[i] ? 1.0 : 0.0;  // at the step's end
  }

  // Positions: the impulse as a force p / h over the step moves them by
  // h/2 G p. A joint stuck at the step's start and at its end is instead
  // held where it was (w.q0): the smooth step's displacement there is h/2
  // of its end rate only up to O(h^3), which would let a stuck joint creep.
  std::array<double, n> r, hold, miss;  // position impulses (dq = G r); 1 where held; held joints' offsets
  for (std::size_t i = 0; i < n; ++i) {
    r[i] = (0.5 * h) * p[i];
    hold[i] = s.stuck[i] * stuck[i];
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t dof = M::kFrictionDof[i];
    double q = s.q[dof];
    for (std::size_t k = 0; k < n; ++k) q += g[k][dof] * r[k];
    miss[i] = w.q0[dof] - q;
  }
  const std::array<double, n> to_hold = solve_friction_block<M>(g, hold, miss);
  for (std::size_t i = 0; i < n; ++i) r[i] += to_hold[i];

  for (std::size_t j = 0; j < s.qd.size(); ++j) {
    double dv = 0.0, dq = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      dv += g[k][j] * p[k];
      dq += g[k][j] * r[k];
    }
    s.qd[j] += dv;
    s.q[j] += dq;
  }
  for (std::size_t i = 0; i < n; ++i) {
    s.friction[i] = p[i] / h;
    s.stuck[i] = stuck[i];
  }
  M::half_angles(s.q, w.half_angles);
}

// After a tree scheme's step, before its body states: the friction
// impulses where the model has joint friction, nothing where it has none.
template <class M>
void tree_friction(typename M::State& s, typename M::Workspace& w) noexcept {
  if constexpr (kFrictionJointsOf<M> > 0) joint_friction<M>(s, w);
}

}  // namespace mbrt::schemes
