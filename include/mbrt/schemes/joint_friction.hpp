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
// otherwise (and for one at rest that the static limit cannot hold: it
// breaks loose), each a constant plus a multiple of the joint's transverse
// reaction. With K, the joints' rate change per unit impulse (here the
// joints' block of M^-1, positive definite), each p_i in turn is the clamped
// value that zeroes its own end-of-step rate: projected Gauss-Seidel, a
// fixed count of sweeps, warm-started from the last step's impulses, then
// one exact solve on the stuck joints (friction_detail, shared with the
// absolute-coordinate schemes: joint_friction_absolute.hpp). The positions
// take the impulse as a force p / h constant over the step,
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

#include "mbrt/flag.hpp"
#include "mbrt/dense_cholesky.hpp"

namespace mbrt::schemes {

// A model's joints with friction: M::kFrictionJoints, or none where the
// model declares none.
template <class M, class = void>
inline constexpr int kFrictionJointsOf = 0;
template <class M>
inline constexpr int kFrictionJointsOf<M, std::void_t<decltype(M::kFrictionJoints)>> = M::kFrictionJoints;

namespace friction_detail {

template <std::size_t n>
using Values = std::array<double, n>;
template <std::size_t n>
using Coupling = Eigen::Matrix<double, static_cast<int>(n), static_cast<int>(n)>;

// The masked system of the exact stuck solve: K_ik where both joints are
// masked, identity where not, b where masked, 0 where not: the work is the
// same whatever the mask.
template <std::size_t n>
void masked_system(const Coupling<n>& k, const Values<n>& mask, const Values<n>& b, Coupling<n>& a,
                   Eigen::Matrix<double, static_cast<int>(n), 1>& x) noexcept {
  constexpr int nn = static_cast<int>(n);
  for (int i = 0; i < nn; ++i) {
    const std::size_t ui = static_cast<std::size_t>(i);
    for (int c = 0; c < nn; ++c) {
      const std::size_t uc = static_cast<std::size_t>(c);
      a(i, c) = mask[ui] * mask[uc] * k(i, c) + (i == c ? 1.0 - mask[ui] : 0.0);
    }
    x(i) = mask[ui] * b[ui];
  }
}

// x with x_i = 0 where mask_i = 0 and sum_c K_ic x_c = b_i where mask_i = 1,
// K positive definite (a tree's block of M^-1): one Cholesky factorization.
template <std::size_t n>
Values<n> solve_masked(const Coupling<n>& k, const Values<n>& mask, const Values<n>& b) noexcept {
  Coupling<n> a;
  Eigen::Matrix<double, static_cast<int>(n), 1> x;
  masked_system<n>(k, mask, b, a, x);
  mbrt::cholesky_in_place(a);
  mbrt::solve_lower(a, x);
  mbrt::solve_lower_transposed(a, x);
  Values<n> out;
  for (std::size_t i = 0; i < n; ++i) out[i] = x(static_cast<int>(i));
  return out;
}

// The impulses p (in: a start within the limits; out: the result) of
// joints whose rates are v0 + K p, |p_i| <= limit_i: projected Gauss-Seidel
// sweeps, each p_i in turn the clamped value that zeroes its own rate; then
// one exact solve (solve_stuck(mask, b), K restricted to the mask) on the
// joints the sweeps left stuck, with the slipping ones at their limits, and
// the limits again. Returns the stuck mask (1 where |p_i| < limit_i).
// The sweeps converge slowly where joints are strongly coupled; the exact
// solve stops them to round-off once the stick/slip split is found.
template <std::size_t n, class StuckSolve>
Values<n> solve_impulses(const Coupling<n>& k, const Values<n>& v0, const Values<n>& limit, int sweeps,
                         const StuckSolve& solve_stuck, Values<n>& p) noexcept {
  constexpr int nn = static_cast<int>(n);
  const auto rate = [&](std::size_t i) {  // joint i's end rate
    double v = v0[i];
    for (std::size_t c = 0; c < n; ++c) v += k(static_cast<int>(i), static_cast<int>(c)) * p[c];
    return v;
  };
  Values<n> v;
  for (std::size_t i = 0; i < n; ++i) v[i] = rate(i);
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    for (int i = 0; i < nn; ++i) {
      const std::size_t ui = static_cast<std::size_t>(i);
      const double next = std::fmin(std::fmax(p[ui] - v[ui] / k(i, i), -limit[ui]), limit[ui]);
      const double change = next - p[ui];
      p[ui] = next;
      for (int c = 0; c < nn; ++c) v[static_cast<std::size_t>(c)] += k(c, i) * change;
    }
  }
  Values<n> stuck, minus_rate;
  for (std::size_t i = 0; i < n; ++i) {
    stuck[i] = flag(std::abs(p[i]) < limit[i]);
    minus_rate[i] = -rate(i);
  }
  const Values<n> to_stop = solve_stuck(stuck, minus_rate);
  for (std::size_t i = 0; i < n; ++i) {
    p[i] = std::fmin(std::fmax(p[i] + to_stop[i], -limit[i]), limit[i]);
    stuck[i] = flag(std::abs(p[i]) < limit[i]);
  }
  return stuck;
}

// The impulses of joints at rest at the step's start (at_rest_i = 1) or
// sliding (0), with limits static_limit and kinetic_limit: solve_impulses
// with the static limit for those at rest, then again with the kinetic
// one for those at rest that it could not hold. A joint breaking loose
// slides under the kinetic limit from its first step of slip (else it
// would feel the static one for that step: an error of (F_s - F_k) h in
// its momentum; the stick-slip belt's position 6.7 times closer to the
// closed form, docs/friction.md). Both passes run every step: fixed work.
template <std::size_t n, class StuckSolve>
Values<n> solve_breaking_loose(const Coupling<n>& k, const Values<n>& v0, const Values<n>& at_rest,
                               const Values<n>& static_limit, const Values<n>& kinetic_limit, int sweeps,
                               const StuckSolve& solve_stuck, Values<n>& p) noexcept {
  Values<n> limit;
  for (std::size_t i = 0; i < n; ++i) {
    limit[i] = at_rest[i] * static_limit[i] + (1.0 - at_rest[i]) * kinetic_limit[i];
    p[i] = std::fmin(std::fmax(p[i], -limit[i]), limit[i]);  // fmax drops a NaN of a failed step
  }
  const Values<n> held = solve_impulses<n>(k, v0, limit, sweeps, solve_stuck, p);
  for (std::size_t i = 0; i < n; ++i) {
    const double loose = at_rest[i] * (1.0 - held[i]);
    limit[i] = loose * kinetic_limit[i] + (1.0 - loose) * limit[i];
    p[i] = std::fmin(std::fmax(p[i], -limit[i]), limit[i]);
  }
  return solve_impulses<n>(k, v0, limit, sweeps, solve_stuck, p);
}

}  // namespace friction_detail

// (s.q, s.qd without friction, w.half_angles of s.q, w.q0 the step's start)
// => (s.q, s.qd with the friction impulses, s.friction, s.stuck,
// w.half_angles). Fixed work whatever the joints do; allocates nothing.
template <class M>
void joint_friction(typename M::State& s, typename M::Workspace& w) noexcept {
  constexpr std::size_t n = M::kFrictionJoints;
  constexpr double h = M::kStep;
  using Values = friction_detail::Values<n>;
  auto& g = w.friction_columns;
  M::friction_response(s, w.half_angles, g);
  friction_detail::Coupling<n> k;  // K_ic = g[c][dof_i]: joint i's rate per unit impulse in joint c
  Values v0;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t c = 0; c < n; ++c) k(static_cast<int>(i), static_cast<int>(c)) = g[c][M::kFrictionDof[i]];
    v0[i] = s.qd[M::kFrictionDof[i]];
  }
  Values load{};  // transverse reactions, where limits depend on them
  if constexpr (M::kFrictionLoads) {
    // At the frictionless step's end: a splitting, like the impulses.
    M::body_states(s.q, w.half_angles, s.qd, s);
    M::friction_loads(s, load);
  }
  Values p, at_rest, static_limit, kinetic_limit;  // impulses (from the last step's), at rest at the start, |p| bounds
  for (std::size_t i = 0; i < n; ++i) {
    // A joint at rest at the step's start (stuck, or started at rest) holds
    // up to its static limit; a sliding one feels the kinetic limit.
    at_rest[i] = flag((s.stuck[i] == 1.0) | (w.qd0[M::kFrictionDof[i]] == 0.0));
    static_limit[i] = (M::kFrictionStaticLimit[i] + M::kFrictionStaticPerLoad[i] * load[i]) * h;
    kinetic_limit[i] = (M::kFrictionLimit[i] + M::kFrictionPerLoad[i] * load[i]) * h;
    p[i] = s.friction[i] * h;
  }
  const auto cholesky = [&](const Values& mask, const Values& b) { return friction_detail::solve_masked<n>(k, mask, b); };
  const Values stuck = friction_detail::solve_breaking_loose<n>(k, v0, at_rest, static_limit, kinetic_limit,
                                                                M::kFrictionSweeps, cholesky, p);

  // Positions: the impulse as a force p / h over the step moves them by
  // h/2 G p. A joint stuck at the step's start and at its end is instead
  // held where it was (w.q0): the smooth step's displacement there is h/2
  // of its end rate only up to O(h^3), which would let a stuck joint creep.
  Values r, hold, miss;  // position impulses (dq = G r); 1 where held; held joints' offsets
  for (std::size_t i = 0; i < n; ++i) {
    r[i] = (0.5 * h) * p[i];
    hold[i] = s.stuck[i] * stuck[i];
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t dof = M::kFrictionDof[i];
    double q = s.q[dof];
    for (std::size_t c = 0; c < n; ++c) q += g[c][dof] * r[c];
    miss[i] = w.q0[dof] - q;
  }
  const Values to_hold = friction_detail::solve_masked<n>(k, hold, miss);
  for (std::size_t i = 0; i < n; ++i) r[i] += to_hold[i];

  for (std::size_t j = 0; j < s.qd.size(); ++j) {
    double dv = 0.0, dq = 0.0;
    for (std::size_t c = 0; c < n; ++c) {
      dv += g[c][j] * p[c];
      dq += g[c][j] * r[c];
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
