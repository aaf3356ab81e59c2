// Contacts and joint friction in one mechanism (a wheel on a braked hub, a
// cart with frictional axles; docs/friction.md, "Contacts and joint
// friction together"), solved together after the smooth step. Contact i's
// velocity changes by K_ci P_i + K_cf p over the contacts' impulses P and the
// friction joints' impulses p, a joint's rate by K_fc P + K_ff p, where
// K_cf is a contact point's velocity in the friction columns X (the joints'
// share taken, joint_friction_absolute.hpp) and K_fc = K_cf^T (the response
// with the joints, M_c^-1, is symmetric).
//
// An active set on the friction joints, a fixed number of passes: the
// friction impulses for the contacts' impulses (the joints' own solver:
// Gauss-Seidel, exact stuck solve, break-loose), then the contacts'
// impulses (their own trials and Gauss-Seidel, contacts.hpp) with the
// joints that stuck held rigid and those that slid at their impulses: the
// contacts' K and velocities become the Schur complement over the stuck
// joints, K_cc - K_cf A^+ K_fc and u + K_cf (s - A^+ (v0 + K_ff s)), with
// A the stuck joints' block of K_ff (least norm: it may be singular) and s
// the sliding joints' impulses. Once the joints' stick/slip split repeats,
// both solves are exact for each other: a rolling wheel whose hub slips, a
// held wheel on an incline (hub and tyre both stuck, which alternating the
// two solves would approach only geometrically, at 0.8 per pass for a disk
// on a carriage of its own mass). The stuck joints' Schur complement is
// shifted by kRigidShift of K's diagonal (a mechanism they lock leaves it at
// round-off). Last, the joints' impulses for the contacts', then the
// contacts for those, none held rigid: where the passes have not settled
// (an impact on an arm whose joints stick and slip), the impulses applied
// still make every contact push, never pull, within its cone, and the
// joints' stay within their limits. Fixed work; nothing allocated.
#pragma once

#include <array>
#include <cstddef>
#include <tuple>
#include <type_traits>

#include <Eigen/Core>

#include "mbrt/contacts.hpp"
#include "mbrt/schemes/joint_friction_absolute.hpp"

namespace mbrt::schemes {

namespace coupled_detail {

// Friction solves, then contact solves, in turn before the last pair: one
// pass to find the joints' stick/slip split, one to confirm it.
inline constexpr int kPasses = 2;

// A mechanism the stuck joints lock leaves its contacts' K at round-off
// (their Schur complement): shifted by this much of K's diagonal, a
// locked contact takes (nearly) no impulse instead of a division by zero.
inline constexpr double kRigidShift = 1e-9;

template <class M>
using FrictionValues = friction_detail::Values<M::kFrictionJoints>;

// Each friction joint's rate change from the contacts' impulses, K_fc P.
template <class M>
FrictionValues<M> from_contacts(const std::array<std::array<Vec3, M::kFrictionJoints>, M::kContacts>& kcf,
                                const std::array<Vec3, M::kContacts>& impulse) noexcept {
  FrictionValues<M> v{};
  for (std::size_t i = 0; i < kcf.size(); ++i) {
    for (std::size_t c = 0; c < v.size(); ++c) v[c] += kcf[i][c].dot(impulse[i]);
  }
  return v;
}

// A^+, A the block of K_ff the stuck mask selects (zero elsewhere), column
// by column through the joints' least-norm stuck solve.
template <class M>
friction_detail::Coupling<M::kFrictionJoints> stuck_inverse(const friction_detail::Coupling<M::kFrictionJoints>& k,
                                                           const FrictionValues<M>& stuck) noexcept {
  constexpr std::size_t n = M::kFrictionJoints;
  friction_detail::Coupling<n> inverse;
  for (std::size_t c = 0; c < n; ++c) {
    FrictionValues<M> e{};
    e[c] = 1.0;
    const FrictionValues<M> column = friction_detail::solve_masked_least_norm<n>(k, stuck, e);
    for (std::size_t i = 0; i < n; ++i) inverse(static_cast<int>(i), static_cast<int>(c)) = column[i];
  }
  return inverse;
}

}  // namespace coupled_detail

// (s after the smooth step, B u = 0; w.c: S factorized at s; w.last_good:
// the step's start) => (s with the contacts' and the friction joints'
// impulses, their outputs; hold: for hold_stuck_joints). Returns the
// joints' share of both as forces, for the multipliers.
template <class M>
typename M::Rows contacts_and_joint_friction(typename M::State& s, typename M::Workspace& w, const Joints<M>& joints,
                                             FrictionHold<M>& hold) noexcept {
  constexpr std::size_t N = static_cast<std::size_t>(M::kContacts);
  constexpr std::size_t n = M::kFrictionJoints;
  constexpr double h = M::kStep;
  using Groups = std::remove_cv_t<decltype(M::kContactGroups)>;
  constexpr int kRows = 3 * static_cast<int>(std::tuple_size<typename Groups::value_type>::value);
  using GroupMatrix = Eigen::Matrix<double, kRows, kRows>;
  const std::array<ContactPoint, N>& data = M::kContactPoints;

  const ContactForces<N> out{s.contact_normal, s.contact_tangential, s.contact_stuck};
  const contact_detail::ContactSetup<M> setup =
      contact_detail::contact_setup<M>(s, out, contact_detail::start_normal_velocities<M>(w.last_good));
  const FrictionSetup<M> f = friction_setup<M>(s, w, joints);

  std::array<std::array<Vec3, n>, N> kcf;  // K_cf: contact i's velocity per unit impulse in joint c
  for (std::size_t i = 0; i < N; ++i) {
    const std::size_t body = static_cast<std::size_t>(data[i].body);
    for (std::size_t c = 0; c < n; ++c) {
      kcf[i][c] = setup.problem.active[i] * contact_detail::point_velocity_of(data[i], setup.problem.frame[i], w.friction_columns[c][body]);
    }
  }
  std::array<GroupMatrix, std::tuple_size<Groups>::value> k;
  std::array<double, N> compliance{};
  std::array<int, N> group_of{};
  for (std::size_t g = 0; g < k.size(); ++g) {
    const auto& group = M::kContactGroups[g];
    for (int l = 0; l < contact_detail::members(group); ++l) group_of[static_cast<std::size_t>(group[static_cast<std::size_t>(l)])] = static_cast<int>(g);
    k[g] = contact_detail::group_matrix<M>(setup.problem, group, static_cast<int>(g), joints, compliance);
  }

  // Warm starts: the last step's impulses (a contact's where it is closed).
  std::array<Vec3, N> impulse;
  std::array<double, N> contact_stuck{};
  for (std::size_t i = 0; i < N; ++i) {
    impulse[i] = setup.problem.active[i] * h *
                 Vec3(out.normal[i], data[i].tangent1.dot(out.tangential[i]), data[i].tangent2.dot(out.tangential[i]));
  }
  coupled_detail::FrictionValues<M> p, rate, joint_stuck;
  for (std::size_t c = 0; c < n; ++c) p[c] = s.friction[c] * h;

  // The contacts' impulses with the joints the mask calls stuck rigid and
  // the others' impulses p fixed; without hold_stuck no joint is rigid and
  // the Schur complement's terms, all zero, are not formed.
  const auto solve_contacts = [&](const coupled_detail::FrictionValues<M>& rigid, bool hold_stuck) {
    const friction_detail::Coupling<n> inverse =
        hold_stuck ? coupled_detail::stuck_inverse<M>(f.k, rigid) : friction_detail::Coupling<n>::Zero();
    Eigen::Matrix<double, static_cast<int>(n), 1> sliding, free_rate;
    for (std::size_t c = 0; c < n; ++c) sliding(static_cast<int>(c)) = (1.0 - rigid[c]) * p[c];
    for (std::size_t c = 0; c < n; ++c) free_rate(static_cast<int>(c)) = f.v0[c] + f.k.row(static_cast<int>(c)).dot(sliding);
    const Eigen::Matrix<double, static_cast<int>(n), 1> joint_impulse = sliding - inverse * free_rate;
    ContactProblem<N> problem = setup.problem;
    std::array<std::array<Vec3, n>, N> held;  // K_cf A^+: a contact's coupling through the rigid joints
    for (std::size_t i = 0; i < N; ++i) {
      Vec3 shift = Vec3::Zero();
      for (std::size_t c = 0; c < n; ++c) {
        shift += kcf[i][c] * joint_impulse(static_cast<int>(c));
        held[i][c].setZero();
        if (!hold_stuck) continue;
        for (std::size_t d = 0; d < n; ++d) held[i][c] += kcf[i][d] * inverse(static_cast<int>(d), static_cast<int>(c));
      }
      problem.start_velocity[i] += shift;
      problem.to_reach[i] -= shift;
    }
    for (std::size_t g = 0; g < k.size(); ++g) {
      const auto& group = M::kContactGroups[g];
      GroupMatrix kg = k[g];
      const int used = contact_detail::members(group);
      if (hold_stuck) {
        for (int r = 0; r < kRows; ++r) kg(r, r) += coupled_detail::kRigidShift * k[g](r, r);
      }
      for (int li = 0; li < used && hold_stuck; ++li) {
        const std::size_t i = static_cast<std::size_t>(group[static_cast<std::size_t>(li)]);
        for (int lj = 0; lj < used; ++lj) {
          const std::size_t j = static_cast<std::size_t>(group[static_cast<std::size_t>(lj)]);
          for (std::size_t c = 0; c < n; ++c) kg.template block<3, 3>(3 * li, 3 * lj) -= held[i][c] * kcf[j][c].transpose();
        }
      }
      contact_detail::solve_group<M>(kg, problem, group, out, impulse, contact_stuck);
    }
  };
  // The joints' impulses for the contacts' (rates v0 + K_fc P).
  const auto solve_joints = [&]() {
    const coupled_detail::FrictionValues<M> by_contacts = coupled_detail::from_contacts<M>(kcf, impulse);
    for (std::size_t c = 0; c < n; ++c) rate[c] = f.v0[c] + by_contacts[c];
    joint_stuck = solve_joint_friction<M>(f, rate, p);
  };
  for (int pass = 0; pass < coupled_detail::kPasses; ++pass) {
    solve_joints();
    solve_contacts(joint_stuck, true);
  }
  solve_joints();
  // Last, the contacts for the joints' impulses as they are, none rigid:
  // whatever the passes left unsettled, the contacts push, never pull, and
  // hold or slide within their cones for the impulses applied.
  solve_contacts(coupled_detail::FrictionValues<M>{}, false);
  typename M::Rows joint_forces = apply_joint_friction<M>(s, w, f, p, joint_stuck, hold);
  joint_forces += contact_detail::apply_impulses<M>(s, joints, setup, impulse, contact_stuck, compliance, group_of, out);
  return joint_forces;
}

}  // namespace mbrt::schemes
