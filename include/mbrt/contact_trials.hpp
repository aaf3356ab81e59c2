// The exact solves of one mechanism's contacts (docs/contact.md): the stick
// trial (every closed contact holds) and the slide trial (every closed
// contact slides under its kinetic friction), each a fixed-size dense solve
// on the mechanism's block of the Delassus matrix K = J M_c^-1 J^T (M_c^-1:
// the bodies' response with their joints, include/mbrt/contacts.hpp). A
// mechanism (one free body, or bodies joined by joints) takes a trial's
// impulses where it holds for all its contacts; the Gauss-Seidel sweeps of
// include/mbrt/contacts.hpp cover the rest (some contacts stick, others slide).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

#include "mbrt/contact_geometry.hpp"
#include "mbrt/dense_cholesky.hpp"

namespace mbrt {

// One mechanism's contacts, indices into the model's; -1 pads the list to
// the size of the mechanism with the most (fixed by the model).
template <std::size_t G>
using ContactGroup = std::array<int, G>;

// What both trials work from, per contact (model order): its geometry, 1
// where it is closed (at or below the plane), the velocity change that
// brings it to rest (normal: to its bounce), and the friction coefficient
// of its stick test (static where it stuck at the last step); target: the
// normal velocity a closed contact ends the step with (its bounce, or 0).
template <std::size_t N>
struct ContactProblem {
  std::array<contact_detail::Frame, N> frame;
  std::array<double, N> active;
  std::array<Vec3, N> start_velocity;  // after the smooth step
  std::array<double, N> target;
  std::array<Vec3, N> to_reach;
  std::array<double, N> limit_factor;
};

namespace contact_detail {

// The group's contacts (its entries before the first pad).
template <std::size_t G>
int members(const ContactGroup<G>& group) noexcept {
  int m = 0;
  while (m < static_cast<int>(G) && group[static_cast<std::size_t>(m)] >= 0) ++m;
  return m;
}

// The mechanism's block of K as if its bodies were free (J M^-1 J^T), lower
// triangle, 3 rows per contact (normal, tangent1, tangent2); an open
// contact's and a pad's rows are identity.
template <std::size_t N, std::size_t G>
Eigen::Matrix<double, 3 * int(G), 3 * int(G)> delassus_matrix(const std::array<ContactPoint, N>& data,
                                                               const ContactProblem<N>& p,
                                                               const ContactGroup<G>& group) noexcept {
  constexpr int n = 3 * static_cast<int>(G);
  Eigen::Matrix<double, n, n> k = Eigen::Matrix<double, n, n>::Zero();
  for (std::size_t li = 0; li < G; ++li) {
    const int i = group[li], ri = 3 * static_cast<int>(li);  // pads (i < 0) come last
    const double active = i < 0 ? 0.0 : p.active[static_cast<std::size_t>(i)];
    for (int a = 0; a < 3; ++a) k(ri + a, ri + a) = 1.0 - active;
    if (i < 0) continue;
    const ContactPoint& c = data[static_cast<std::size_t>(i)];
    const Frame& fi = p.frame[static_cast<std::size_t>(i)];
    for (std::size_t lj = 0; lj <= li; ++lj) {
      const int j = group[lj], rj = 3 * static_cast<int>(lj);
      if (j < 0) continue;
      const Frame& fj = p.frame[static_cast<std::size_t>(j)];
      // Contacts on different bodies of a mechanism couple through its joints
      // only (their part is added by the caller).
      const double same_body = static_cast<double>(data[static_cast<std::size_t>(j)].body == c.body);
      const double both = active * p.active[static_cast<std::size_t>(j)] * same_body;
      for (int a = 0; a < 3; ++a) {
        const Vec3 m = c.inverse_inertia * fi.arm[a];
        for (int b = 0; b < 3; ++b) k(ri + a, rj + b) += both * (fj.arm[b].dot(m) + (a == b ? c.inverse_mass : 0.0));
      }
    }
  }
  return k;
}

// A body on several contacts is statically indeterminate: many impulses
// give it the same motion. A shift eps D of K's diagonal picks the one of
// least weighted norm (the limit of (K + eps D)^-1 b; Tikhonov), here with
// eps D = 1e-10 diag(K) times weight, and one refinement on K itself. Only
// the leading `used` rows (the body's contacts; pads follow) are solved, so
// a body pays for its own contacts, not for the body with the most.
template <int n>
Eigen::Matrix<double, n, 1> least_norm_solve(const Eigen::Matrix<double, n, n>& k, const Eigen::Matrix<double, n, 1>& b,
                                             const Eigen::Matrix<double, n, 1>& weight, int rows) noexcept {
  const int used = std::min(std::max(rows, 0), n);
  Eigen::Matrix<double, n, n> l = Eigen::Matrix<double, n, n>::Zero();
  for (int j = 0; j < used; ++j) {  // Cholesky of the shifted leading block, lower triangle
    double d = k(j, j) * (1.0 + 1e-10 * weight[j]);
    for (int q = 0; q < j; ++q) d -= l(j, q) * l(j, q);
    // 1 where d > 0 (else a usable pivot of 1: a row dependent on the ones
    // before it, as a contact's tangent held by a joint), from the sign bit:
    // a comparison here compiled to a branch.
    const double positive = 0.5 + 0.5 * std::copysign(1.0, d - 1e-300);
    l(j, j) = std::sqrt(positive * d + (1.0 - positive));
    for (int i = j + 1; i < used; ++i) {
      double e = k(i, j);
      for (int q = 0; q < j; ++q) e -= l(i, q) * l(j, q);
      l(i, j) = e / l(j, j);
    }
  }
  const auto solve = [&](Eigen::Matrix<double, n, 1>& y) {
    for (int i = 0; i < used; ++i) {
      for (int q = 0; q < i; ++q) y[i] -= l(i, q) * y[q];
      y[i] /= l(i, i);
    }
    for (int i = used - 1; i >= 0; --i) {
      for (int q = i + 1; q < used; ++q) y[i] -= l(q, i) * y[q];
      y[i] /= l(i, i);
    }
  };
  Eigen::Matrix<double, n, 1> x = Eigen::Matrix<double, n, 1>::Zero();
  for (int i = 0; i < used; ++i) x[i] = b[i];
  solve(x);
  Eigen::Matrix<double, n, 1> r = Eigen::Matrix<double, n, 1>::Zero();
  for (int i = 0; i < used; ++i) {  // b - K x, K from its lower triangle
    double e = b[i];
    for (int q = 0; q < used; ++q) e -= (q <= i ? k(i, q) : k(q, i)) * x[q];
    r[i] = e;
  }
  solve(r);
  return x + r;
}

}  // namespace contact_detail

// The stick trial: the impulses with which every closed contact of the body
// holds (normal approach speed to its target, no slip), solved exactly for
// all of them at once. Of the impulses that hold a body on several
// contacts, first the least-norm one, then the one weighted by the inverse
// of each contact's normal impulse in it, which shares the friction out in
// proportion to the normal loads, as the cones do (the least-norm impulses
// leave internal friction forces that use them up). Returns whether every
// closed contact pushes and stays inside its cone.
template <std::size_t N, std::size_t G>
bool stick_trial(const Eigen::Matrix<double, 3 * int(G), 3 * int(G)>& k, const ContactProblem<N>& p,
                 const ContactGroup<G>& group, std::array<Vec3, N>& impulse) noexcept {
  constexpr int n = 3 * static_cast<int>(G);
  Eigen::Matrix<double, n, 1> b = Eigen::Matrix<double, n, 1>::Zero(), weight = Eigen::Matrix<double, n, 1>::Ones();
  for (std::size_t l = 0; l < G; ++l) {
    if (group[l] >= 0) {
      const std::size_t i = static_cast<std::size_t>(group[l]);
      b.template segment<3>(3 * static_cast<int>(l)) = p.active[i] * p.to_reach[i];
    }
  }
  const int used = 3 * contact_detail::members(group);
  const Eigen::Matrix<double, n, 1> least = contact_detail::least_norm_solve<n>(k, b, weight, used);
  double mean = 1e-300;
  for (int r = 0; r < used; r += 3) mean += std::abs(least[r]) / static_cast<double>(used / 3);
  for (std::size_t l = 0; l < G; ++l) {
    weight.template segment<3>(3 * static_cast<int>(l)).setConstant(mean / contact_detail::at_least(least[3 * static_cast<int>(l)], 1e-6 * mean));
  }
  const Eigen::Matrix<double, n, 1> x = contact_detail::least_norm_solve<n>(k, b, weight, used);
  bool holds = true;
  for (std::size_t l = 0; l < G; ++l) {
    if (group[l] < 0) continue;
    const std::size_t i = static_cast<std::size_t>(group[l]);
    impulse[i] = x.template segment<3>(3 * static_cast<int>(l));
    const bool pushes = impulse[i][0] >= 0.0;
    const bool in_cone = impulse[i].template tail<2>().norm() <= p.limit_factor[i] * impulse[i][0];
    holds = holds & pushes & in_cone;  // & not &&: the same work whatever the outcome
  }
  return holds;
}

// The slide trial, where the stick trial fails: every closed contact of the
// body slides with its kinetic friction mu_k P_n along the stick trial's
// friction direction d (the way the loads drive it, against its slip), its
// normal approach speed to its target. With P_t = mu_k P_n d the normal rows
// of K give A P_n = b, A = K_nn + K_nt mu_k D; of its solutions the
// least-norm one (normal equations shifted as in least_norm_solve), so
// loads on a statically indeterminate body do not twist it. Returns whether
// every closed contact pushes and still slides against its friction at the
// step's end.
template <std::size_t N, std::size_t G>
bool slide_trial(const std::array<ContactPoint, N>& data, const Eigen::Matrix<double, 3 * int(G), 3 * int(G)>& k,
                 const ContactProblem<N>& p, const ContactGroup<G>& group, const std::array<Vec3, N>& held,
                 std::array<Vec3, N>& impulse) noexcept {
  constexpr int n = static_cast<int>(G);
  const int used = contact_detail::members(group);
  const auto block = [&](int r, int c) {  // K's 3x3 block, from its lower triangle
    return r >= c ? Mat3(k.template block<3, 3>(3 * r, 3 * c)) : Mat3(k.template block<3, 3>(3 * c, 3 * r).transpose());
  };
  std::array<Vec3, G> unit;  // the impulse per unit normal impulse: (1, mu_k d)
  Eigen::Matrix<double, n, 1> b = Eigen::Matrix<double, n, 1>::Zero();
  for (int l = 0; l < used; ++l) {
    const std::size_t i = static_cast<std::size_t>(group[static_cast<std::size_t>(l)]);
    const Eigen::Vector2d hold = held[i].template tail<2>();
    unit[static_cast<std::size_t>(l)] << 1.0, (p.active[i] * data[i].mu_kinetic / contact_detail::at_least(hold.norm(), 1e-300)) * hold;
    b[l] = p.active[i] * p.to_reach[i][0];
  }
  Eigen::Matrix<double, n, n> a = Eigen::Matrix<double, n, n>::Zero();
  for (int r = 0; r < used; ++r) {
    for (int c = 0; c < used; ++c) a(r, c) = block(r, c).row(0).dot(unit[static_cast<std::size_t>(c)]);
  }
  const Eigen::Matrix<double, n, 1> normal_load = contact_detail::least_norm_solve<n>(
      Eigen::Matrix<double, n, n>(a.transpose() * a), Eigen::Matrix<double, n, 1>(a.transpose() * b),
      Eigen::Matrix<double, n, 1>::Ones(), used);
  bool slides = true;
  for (int l = 0; l < used; ++l) {
    const std::size_t i = static_cast<std::size_t>(group[static_cast<std::size_t>(l)]);
    impulse[i] = normal_load[l] * unit[static_cast<std::size_t>(l)];
    // The end-of-step slip against the friction: (K P - velocity change to stop) . d <= 0.
    Vec3 change = Vec3::Zero();
    for (int m = 0; m < used; ++m) change += block(l, m) * (normal_load[m] * unit[static_cast<std::size_t>(m)]);
    const double slip = (change - p.to_reach[i]).template tail<2>().dot(unit[static_cast<std::size_t>(l)].template tail<2>());
    slides = slides & (impulse[i][0] >= 0.0) & (slip <= 0.0);
  }
  return slides;
}

}  // namespace mbrt
