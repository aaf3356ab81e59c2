// Coulomb friction in revolute and prismatic joints under the schemes in
// absolute coordinates (docs/friction.md): the velocity-level impulses of
// the tree's joint friction (joint_friction.hpp; Moreau 1988, Stewart
// 2000), here on the joint rates g_i u, g_i the joint coordinate's row
// over the two bodies' [v; w_body]. A unit impulse along joint c moves the
// bodies by X_c = M_c^-1 g_c^T, M_c^-1 = M^-1 - M^-1 B^T S^-1 B M^-1 (the
// joints take their share, mechanism_response.hpp), so joint i's rate
// changes by K_ic = g_i X_c. K is singular where friction joints close a
// loop or a joint cannot turn (several pins of one four-bar): the exact
// stuck solve takes the least-norm impulses there.
//
// M provides kFrictionJoints, kFrictionBodies (each joint's two bodies, -1
// for the ground), kFrictionRevolute, the limits of joint_friction.hpp,
// kFrictionLoads with friction_loads (the transverse reactions from the
// multipliers), kFrictionSweeps, friction_rows (each joint's coordinate
// and row at a state) and friction_columns (M^-1 g^T, without the joints);
// State has friction and stuck; Workspace has friction_columns.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

#include <Eigen/Core>

#include "mbrt/flag.hpp"
#include "mbrt/constraint_kernels.hpp"
#include "mbrt/contact_trials.hpp"
#include "mbrt/joint_coordinates.hpp"
#include "mbrt/mechanism_response.hpp"
#include "mbrt/schemes/joint_friction.hpp"

namespace mbrt::schemes {

namespace friction_detail {

// g_i x: a friction joint's rate for body velocities (or responses) x.
template <class M>
double joint_rate(int joint, const JointRow& row, const typename M::BodyVectors& x) noexcept {
  const std::array<int, 2>& bodies = M::kFrictionBodies[static_cast<std::size_t>(joint)];
  double v = 0.0;
  if (bodies[0] >= 0) v += row.J1.dot(x[static_cast<std::size_t>(bodies[0])]);
  if (bodies[1] >= 0) v += row.J2.dot(x[static_cast<std::size_t>(bodies[1])]);
  return v;
}

// The masked solve for a K that may be singular: least norm (Tikhonov
// shift 1e-10 of the diagonal, contact_trials.hpp), the same work whatever
// the mask.
template <std::size_t n>
Values<n> solve_masked_least_norm(const Coupling<n>& k, const Values<n>& mask, const Values<n>& b) noexcept {
  constexpr int nn = static_cast<int>(n);
  Coupling<n> a;
  Eigen::Matrix<double, nn, 1> x;
  masked_system<n>(k, mask, b, a, x);
  const Eigen::Matrix<double, nn, 1> y =
      contact_detail::least_norm_solve<nn>(a, x, Eigen::Matrix<double, nn, 1>::Ones(), nn);
  Values<n> out;
  for (std::size_t i = 0; i < n; ++i) out[i] = y(static_cast<int>(i));
  return out;
}

// (dq per joint impulse, coefficients) => sum_c x_c r_c over the bodies.
template <class M>
typename M::BodyVectors combine(const typename M::FrictionColumns& x, const Values<M::kFrictionJoints>& r) noexcept {
  typename M::BodyVectors out;
  for (auto& e : out) e.setZero();
  for (std::size_t c = 0; c < x.size(); ++c) {
    for (std::size_t b = 0; b < out.size(); ++b) out[b] += r[c] * x[c][b];
  }
  return out;
}

}  // namespace friction_detail

// What holding the stuck joints after the scheme's position correction
// needs: K, which joints stuck through the whole step, and where they
// started.
template <class M>
struct FrictionHold {
  friction_detail::Coupling<M::kFrictionJoints> k;
  friction_detail::Values<M::kFrictionJoints> hold;
  std::array<JointRow, M::kFrictionJoints> start;
};

// A step's joint-friction problem: each joint's row at the step's end and
// start, the columns X (w.friction_columns, the joints' share taken) with
// the joints' impulses z per unit friction impulse, K, the joints' rates
// v0 after the smooth step, which were at rest at the step's start (stuck,
// or started at rest: they hold up to the static limit), and the limits
// (impulses, from the multipliers the smooth step ended with).
template <class M>
struct FrictionSetup {
  static constexpr std::size_t n = M::kFrictionJoints;
  using Values = friction_detail::Values<n>;
  std::array<JointRow, n> rows, start_rows;
  std::array<typename M::Rows, n> z;
  friction_detail::Coupling<n> k;
  Values v0, at_rest, static_limit, kinetic_limit;
};

// (s after the smooth step; w.c: S factorized at s; w.last_good: the
// step's start) => (the setup; w.friction_columns: X).
template <class M>
FrictionSetup<M> friction_setup(const typename M::State& s, typename M::Workspace& w, const Joints<M>& joints) noexcept {
  constexpr std::size_t n = M::kFrictionJoints;
  constexpr int nn = static_cast<int>(n);
  constexpr double h = M::kStep;
  FrictionSetup<M> f;
  M::friction_rows(s, f.rows);
  M::friction_rows(w.last_good, f.start_rows);
  auto& x = w.friction_columns;
  M::friction_columns(s, f.rows, x);
  for (std::size_t c = 0; c < n; ++c) f.z[c] = joints.constrain(x[c]);
  for (int i = 0; i < nn; ++i) {
    for (int c = 0; c < nn; ++c) f.k(i, c) = friction_detail::joint_rate<M>(i, f.rows[static_cast<std::size_t>(i)], x[static_cast<std::size_t>(c)]);
  }
  f.k = (0.5 * (f.k + f.k.transpose())).eval();  // symmetric but for round-off
  const typename M::BodyVectors u = M::generalized_velocities(s);
  const typename M::BodyVectors u0 = M::generalized_velocities(w.last_good);
  friction_detail::Values<n> load{};
  if constexpr (M::kFrictionLoads) M::friction_loads(s, load);
  for (std::size_t i = 0; i < n; ++i) {
    const int ji = static_cast<int>(i);
    f.v0[i] = friction_detail::joint_rate<M>(ji, f.rows[i], u);
    // Bitwise |, not ||: the same instructions whatever the state.
    f.at_rest[i] = flag((s.stuck[i] == 1.0) | (friction_detail::joint_rate<M>(ji, f.start_rows[i], u0) == 0.0));
    f.static_limit[i] = (M::kFrictionStaticLimit[i] + M::kFrictionStaticPerLoad[i] * load[i]) * h;
    f.kinetic_limit[i] = (M::kFrictionLimit[i] + M::kFrictionPerLoad[i] * load[i]) * h;
  }
  return f;
}

// The impulses p (in: a start, the last step's; out: the result) of the
// friction joints with rates v0 + K p (friction_detail::solve_breaking_loose,
// the least-norm stuck solve: K may be singular). Returns the stuck mask.
template <class M>
friction_detail::Values<M::kFrictionJoints> solve_joint_friction(const FrictionSetup<M>& f,
                                                                const friction_detail::Values<M::kFrictionJoints>& v0,
                                                                friction_detail::Values<M::kFrictionJoints>& p) noexcept {
  constexpr std::size_t n = M::kFrictionJoints;
  const auto least_norm = [&](const friction_detail::Values<n>& mask, const friction_detail::Values<n>& b) {
    return friction_detail::solve_masked_least_norm<n>(f.k, mask, b);
  };
  return friction_detail::solve_breaking_loose<n>(f.k, v0, f.at_rest, f.static_limit, f.kinetic_limit, M::kFrictionSweeps,
                                                  least_norm, p);
}

// (s; the impulses p and stuck mask) => (s with them: velocities, h/2 of
// their change on the positions, s.friction, s.stuck; hold: for
// hold_stuck_joints). Returns the joints' share of the impulses as forces,
// z / h, for the multipliers.
template <class M>
typename M::Rows apply_joint_friction(typename M::State& s, const typename M::Workspace& w, const FrictionSetup<M>& f,
                                      const friction_detail::Values<M::kFrictionJoints>& p,
                                      const friction_detail::Values<M::kFrictionJoints>& stuck, FrictionHold<M>& hold) noexcept {
  constexpr std::size_t n = M::kFrictionJoints;
  constexpr double h = M::kStep;
  typename M::BodyVectors change = friction_detail::combine<M>(w.friction_columns, p);
  typename M::BodyVectors v = M::generalized_velocities(s);
  for (std::size_t b = 0; b < v.size(); ++b) {
    v[b] += change[b];
    change[b] *= 0.5 * h;  // the impulse as a force p / h over the step
  }
  M::set_velocities(v, s);
  M::displace(change, s);
  typename M::Rows joint_forces = M::Rows::Zero();
  for (std::size_t c = 0; c < n; ++c) joint_forces += (p[c] / h) * f.z[c];
  hold.k = f.k;
  for (std::size_t i = 0; i < n; ++i) {
    hold.hold[i] = s.stuck[i] * stuck[i];
    hold.start[i] = f.start_rows[i];
    s.friction[i] = p[i] / h;
    s.stuck[i] = stuck[i];
  }
  return joint_forces;
}

// (s after the smooth step and its contacts; w.c: S factorized at s;
// w.last_good: the step's start) => (s with the friction impulses,
// apply_joint_friction). A joint at rest at the step's start holds up to
// its static limit, one that breaks loose slides under the kinetic one.
// Fixed work, no allocation.
template <class M>
typename M::Rows absolute_joint_friction(typename M::State& s, typename M::Workspace& w, const Joints<M>& joints,
                                         FrictionHold<M>& hold) noexcept {
  const FrictionSetup<M> f = friction_setup<M>(s, w, joints);
  friction_detail::Values<M::kFrictionJoints> p;
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = s.friction[i] * M::kStep;
  const friction_detail::Values<M::kFrictionJoints> stuck = solve_joint_friction<M>(f, f.v0, p);
  return apply_joint_friction<M>(s, w, f, p, stuck, hold);
}

// After the scheme has put the positions back on the joints: each joint
// stuck through the whole step moved back to where it started (the smooth
// step's displacement there is h/2 of its end rate only up to O(h^3), and
// the position correction moves it at second order: it would creep), along
// the columns X, so the joints stay closed to first order.
template <class M>
void hold_stuck_joints(typename M::State& s, const typename M::Workspace& w, const FrictionHold<M>& hold) noexcept {
  constexpr std::size_t n = M::kFrictionJoints;
  std::array<JointRow, n> rows;
  M::friction_rows(s, rows);
  friction_detail::Values<n> miss;
  for (std::size_t i = 0; i < n; ++i) miss[i] = joint_offset(hold.start[i], rows[i], M::kFrictionRevolute[i]);
  const friction_detail::Values<n> r = friction_detail::solve_masked_least_norm<n>(hold.k, hold.hold, miss);
  M::displace(friction_detail::combine<M>(w.friction_columns, r), s);
}

}  // namespace mbrt::schemes
