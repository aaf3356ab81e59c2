// Unilateral frictional contacts of free bodies with fixed planes
// (docs/contact.md). After the scheme's smooth step, velocity-level impulses
// (Moreau 1988, "Unilateral contact and dry friction in finite freedom
// dynamics"; Stewart 2000, "Rigid-body dynamics with friction and impact",
// SIAM Review 42(1)) make every touching contact push, never pull, and either
// stick or slide under Coulomb friction: a contact stuck at the last step
// holds up to mu_static times its normal impulse, a sliding one feels
// mu_kinetic. Projected Gauss-Seidel over the contacts with a fixed number of
// sweeps, each contact's normal and tangential impulses solved on its own
// 3x3 block of the Delassus matrix; positions take the impulses as a
// constant force over the step (h/2 of the velocity change), then any
// penetration left by an impact is projected out along the normals.
// Fixed work whatever touches, sticks or slides; nothing allocated.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <type_traits>

#include "mbrt/dense_cholesky.hpp"
#include "mbrt/rotation.hpp"
#include "mbrt/types.hpp"

namespace mbrt {

// A contact's constant data (generated from the model file).
struct ContactPoint {
  Vec3 offset;                      // body axes: from the COM to the point, or to the sphere's centre
  double radius;                    // sphere; 0 for a point
  Vec3 plane_point;                 // world
  Vec3 normal, tangent1, tangent2;  // world, right-handed, normal out of the ground
  double inverse_mass;
  Mat3 inverse_inertia;             // body axes; zero for a particle
  double mu_static, mu_kinetic, restitution;
};

// Where a contact's body keeps its state; p and w are null for a particle.
struct ContactBody {
  Vec3* r;
  EulerParameters* p;
  Vec3* v;
  Vec3* w;
};

// What the last step's impulses were, per contact (State's contact fields):
// normal force and tangential force (world) as impulse / h, and 1 where the
// contact stuck, 0 where it slid or was open.
template <std::size_t N>
struct ContactForces {
  std::array<double, N>& normal;
  std::array<Vec3, N>& tangential;
  std::array<double, N>& stuck;
};

namespace contact_detail {

// A contact's geometry at the current positions: the direction of each
// impulse component in body-axes angular terms (rho x R^T e), and the gap.
struct Frame {
  Mat3 rt;             // R^T (identity for a particle)
  Vec3 rho;            // body axes: from the COM to the contact point
  std::array<Vec3, 3> arm;  // rho x R^T e_k, k = normal, tangent1, tangent2
  double gap;          // distance of the contact point above the plane (m)
};

inline Frame frame_of(const ContactPoint& c, const ContactBody& b) noexcept {
  Frame f;
  f.rt = b.p ? Mat3(rotation_matrix(*b.p).transpose()) : Mat3(Mat3::Identity());
  f.rho = c.offset - c.radius * (f.rt * c.normal);
  const Vec3 point = *b.r + f.rt.transpose() * f.rho;
  f.gap = c.normal.dot(point - c.plane_point);
  const Vec3* e[3] = {&c.normal, &c.tangent1, &c.tangent2};
  for (int k = 0; k < 3; ++k) f.arm[k] = b.p ? Vec3(f.rho.cross(f.rt * *e[k])) : Vec3(Vec3::Zero());
  return f;
}

// The contact point's velocity along (normal, tangent1, tangent2).
inline Vec3 point_velocity(const ContactPoint& c, const ContactBody& b, const Frame& f) noexcept {
  Vec3 u(c.normal.dot(*b.v), c.tangent1.dot(*b.v), c.tangent2.dot(*b.v));
  if (b.w) {
    for (int k = 0; k < 3; ++k) u[k] += f.arm[k].dot(*b.w);
  }
  return u;
}

// The body's velocity change from an impulse dP (normal, tangent1, tangent2) at the point.
inline void apply_impulse(const ContactPoint& c, const ContactBody& b, const Frame& f, const Vec3& dp) noexcept {
  *b.v += c.inverse_mass * (dp[0] * c.normal + dp[1] * c.tangent1 + dp[2] * c.tangent2);
  if (b.w) *b.w += c.inverse_inertia * (dp[0] * f.arm[0] + dp[1] * f.arm[1] + dp[2] * f.arm[2]);
}

// The body's displacement from a position impulse dP: translation and a
// body-axes rotation, the same directions as the velocity change.
inline void displace(const ContactPoint& c, const ContactBody& b, const Frame& f, const Vec3& dp) noexcept {
  *b.r += c.inverse_mass * (dp[0] * c.normal + dp[1] * c.tangent1 + dp[2] * c.tangent2);
  if (b.p) {
    const Vec3 theta = c.inverse_inertia * (dp[0] * f.arm[0] + dp[1] * f.arm[1] + dp[2] * f.arm[2]);
    *b.p = quaternion_product(*b.p, cayley_increment(theta));
  }
}

// The contact's 3x3 block of the Delassus matrix J M^-1 J^T.
inline Mat3 delassus_block(const ContactPoint& c, const Frame& f) noexcept {
  Mat3 d = c.inverse_mass * Mat3::Identity();
  for (int k = 0; k < 3; ++k) {
    const Vec3 m = c.inverse_inertia * f.arm[k];
    for (int l = 0; l < 3; ++l) d(l, k) += f.arm[l].dot(m);
  }
  return d;
}

// The Delassus matrix K = J M^-1 J^T of all contacts (3 rows each: normal,
// tangent1, tangent2), its lower triangle; contacts on different bodies do
// not couple, and an open contact's rows are made identity.
template <std::size_t N>
Eigen::Matrix<double, 3 * int(N), 3 * int(N)> delassus_matrix(const std::array<ContactPoint, N>& data,
                                                               const std::array<ContactBody, N>& bodies,
                                                               const std::array<Frame, N>& frame,
                                                               const std::array<double, N>& active) noexcept {
  constexpr int n = 3 * static_cast<int>(N);
  Eigen::Matrix<double, n, n> k = Eigen::Matrix<double, n, n>::Zero();
  for (std::size_t i = 0; i < N; ++i) {
    const int ri = 3 * static_cast<int>(i);
    for (std::size_t j = 0; j <= i; ++j) {
      if (bodies[i].v != bodies[j].v) continue;  // which bodies share a contact is fixed by the model
      const int rj = 3 * static_cast<int>(j);
      for (int a = 0; a < 3; ++a) {
        const Vec3 m = data[i].inverse_inertia * frame[i].arm[a];
        for (int c = 0; c < 3; ++c) {
          k(ri + a, rj + c) = active[i] * active[j] * (frame[j].arm[c].dot(m) + (a == c ? data[i].inverse_mass : 0.0));
        }
      }
    }
    for (int a = 0; a < 3; ++a) k(ri + a, ri + a) += 1.0 - active[i];
  }
  return k;
}

// A body on several contacts is statically indeterminate: many impulses
// give it the same motion. A shift eps D of K's diagonal picks the one of
// least weighted norm (the limit of (K + eps D)^-1 b; Tikhonov), here with
// eps D = 1e-10 diag(K) times weight, and one refinement on K itself.
template <int n>
Eigen::Matrix<double, n, 1> least_norm_solve(const Eigen::Matrix<double, n, n>& k, const Eigen::Matrix<double, n, 1>& b,
                                             const Eigen::Matrix<double, n, 1>& weight) noexcept {
  Eigen::Matrix<double, n, n> l = k;
  for (int r = 0; r < n; ++r) l(r, r) += 1e-10 * k(r, r) * weight[r];
  Eigen::Matrix<double, n, 1> x = b;
  cholesky_in_place(l);
  solve_lower(l, x);
  solve_lower_transposed(l, x);
  Eigen::Matrix<double, n, 1> r = b - k.template selfadjointView<Eigen::Lower>() * x;
  solve_lower(l, r);
  solve_lower_transposed(l, r);
  return x + r;
}

}  // namespace contact_detail

// The stick trial: the impulses with which every closed contact holds
// (normal approach speed to its target, no slip), solved exactly for all of
// them at once. Of the impulses that hold a body on several contacts, first
// the least-norm one, then the one weighted by the inverse of each
// contact's normal impulse in it, which shares the friction out in
// proportion to the normal loads, as the cones do (the least-norm impulses
// leave internal friction forces that use them up). Accepted where every
// closed contact pushes and stays inside its cone (the static one where it
// stuck at the last step).
template <std::size_t N>
void stick_trial(const Eigen::Matrix<double, 3 * int(N), 3 * int(N)>& k, const std::array<double, N>& active,
                 const std::array<Vec3, N>& to_reach, const std::array<double, N>& limit_factor,
                 std::array<Vec3, N>& impulse, std::array<bool, N>& holds) noexcept {
  constexpr int n = 3 * static_cast<int>(N);
  Eigen::Matrix<double, n, 1> b, weight = Eigen::Matrix<double, n, 1>::Ones();
  for (std::size_t i = 0; i < N; ++i) b.template segment<3>(3 * static_cast<int>(i)) = active[i] * to_reach[i];
  const Eigen::Matrix<double, n, 1> least = contact_detail::least_norm_solve<n>(k, b, weight);
  double mean = 1e-300;
  for (std::size_t i = 0; i < N; ++i) mean += active[i] * std::abs(least[3 * static_cast<int>(i)]) / static_cast<double>(N);
  for (std::size_t i = 0; i < N; ++i) {
    weight.template segment<3>(3 * static_cast<int>(i)).setConstant(mean / std::max(least[3 * static_cast<int>(i)], 1e-6 * mean));
  }
  const Eigen::Matrix<double, n, 1> x = contact_detail::least_norm_solve<n>(k, b, weight);
  for (std::size_t i = 0; i < N; ++i) {
    impulse[i] = x.template segment<3>(3 * static_cast<int>(i));
    holds[i] = impulse[i][0] >= 0.0 && impulse[i].template tail<2>().norm() <= limit_factor[i] * impulse[i][0];
  }
}

// The slide trial, where the stick trial fails: every closed contact slides
// with its kinetic friction mu_k P_n along the stick trial's friction
// direction d (the way the loads drive it, against its slip), its normal
// approach speed to its target. With P_t = mu_k P_n d the normal rows of K
// give A P_n = b, A = K_nn + K_nt mu_k D; of its solutions the least-norm
// one (normal equations shifted as in least_norm_solve), so loads on a
// statically indeterminate body do not twist it. Accepted where every closed
// contact pushes and still slides against its friction at the step's end.
template <std::size_t N>
void slide_trial(const std::array<ContactPoint, N>& data, const Eigen::Matrix<double, 3 * int(N), 3 * int(N)>& lower,
                 const std::array<double, N>& active, const std::array<Vec3, N>& to_reach,
                 const std::array<Vec3, N>& held, std::array<Vec3, N>& impulse, std::array<bool, N>& slides) noexcept {
  constexpr int n = static_cast<int>(N);
  const Eigen::Matrix<double, 3 * n, 3 * n> k = lower.template selfadjointView<Eigen::Lower>();
  Eigen::Matrix<double, n, n> a;
  Eigen::Matrix<double, n, 1> b;
  std::array<Vec3, N> unit;  // the impulse per unit normal impulse: (1, mu_k d)
  for (std::size_t j = 0; j < N; ++j) {
    const Eigen::Vector2d hold = held[j].template tail<2>();
    unit[j] << 1.0, (active[j] * data[j].mu_kinetic / std::max(hold.norm(), 1e-300)) * hold;
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) a(i, j) = k.template block<1, 3>(3 * i, 3 * j).dot(unit[static_cast<std::size_t>(j)]);
    b[i] = active[static_cast<std::size_t>(i)] * to_reach[static_cast<std::size_t>(i)][0];
  }
  const Eigen::Matrix<double, n, n> normal = a.transpose() * a;
  const Eigen::Matrix<double, n, 1> normal_load =
      contact_detail::least_norm_solve<n>(normal, a.transpose() * b, Eigen::Matrix<double, n, 1>::Ones());
  for (std::size_t i = 0; i < N; ++i) impulse[i] = normal_load[static_cast<int>(i)] * unit[i];
  for (std::size_t i = 0; i < N; ++i) {
    // The end-of-step slip against the friction: (K P - velocity change to stop) . d <= 0.
    Vec3 change = Vec3::Zero();
    for (std::size_t j = 0; j < N; ++j) change += k.template block<3, 3>(3 * static_cast<int>(i), 3 * static_cast<int>(j)) * impulse[j];
    const double slip = (change - to_reach[i]).template tail<2>().dot(unit[i].template tail<2>());
    slides[i] = impulse[i][0] >= 0.0 && slip <= 0.0;
  }
}

// (positions and velocities after the smooth step, out of the last step,
// each contact point's normal velocity at the step's start) => (positions,
// velocities, out). h: the step; sweeps: Gauss-Seidel sweeps (fixed at
// generation); bounce_speed: the approach speed below which a contact does
// not bounce (so a body at rest settles instead of chattering).
template <std::size_t N>
void resolve_contacts(const std::array<ContactPoint, N>& data, const std::array<ContactBody, N>& bodies, double h,
                      int sweeps, double bounce_speed, const std::array<double, N>& start_normal_velocity,
                      ContactForces<N> out) noexcept {
  using contact_detail::Frame;
  std::array<Frame, N> frame;
  std::array<Mat3, N> block;
  std::array<Eigen::Matrix2d, N> tangent_inverse;
  std::array<double, N> active, normal_target, limit_factor;
  std::array<Vec3, N> to_reach, start_v, start_w;  // velocity changes to stick; the bodies' velocities
  for (std::size_t i = 0; i < N; ++i) {
    const ContactPoint& c = data[i];
    frame[i] = contact_detail::frame_of(c, bodies[i]);
    block[i] = contact_detail::delassus_block(c, frame[i]);
    const Mat3& d = block[i];
    const double det = d(1, 1) * d(2, 2) - d(1, 2) * d(2, 1);
    tangent_inverse[i] << d(2, 2) / det, -d(1, 2) / det, -d(2, 1) / det, d(1, 1) / det;
    active[i] = frame[i].gap <= 0.0 ? 1.0 : 0.0;
    const Vec3 u = contact_detail::point_velocity(c, bodies[i], frame[i]);
    // A bounce (Newton's law, separation = e approach) at the approach speed
    // averaged over the step, less the smooth loads' half step after it: the
    // impact's time within the step is unknown, and this is the end-of-step
    // speed averaged over it, which leaves the bounce heights unbiased.
    const double average = 0.5 * (start_normal_velocity[i] + u[0]);
    const double bounce = -c.restitution * average + 0.5 * (u[0] - start_normal_velocity[i]);
    normal_target[i] = u[0] < -bounce_speed ? std::max(bounce, 0.0) : 0.0;
    to_reach[i] = Vec3(normal_target[i], 0.0, 0.0) - u;
    limit_factor[i] = out.stuck[i] > 0.0 ? c.mu_static : c.mu_kinetic;
    start_v[i] = *bodies[i].v;
    start_w[i] = bodies[i].w ? *bodies[i].w : Vec3(Vec3::Zero());
  }
  const auto k = contact_detail::delassus_matrix(data, bodies, frame, active);
  std::array<Vec3, N> held, slid;
  std::array<bool, N> holds, slides;
  stick_trial(k, active, to_reach, limit_factor, held, holds);
  slide_trial(data, k, active, to_reach, held, slid, slides);
  // Each body takes a trial where it holds for all its contacts: sticks
  // where they all stick, else slides where they all slide.
  std::array<std::size_t, N> owner;  // the index of the body's first contact
  std::array<bool, N> body_holds, body_slides;
  for (std::size_t i = 0; i < N; ++i) {
    owner[i] = i;
    for (std::size_t j = 0; j < i; ++j) {
      if (bodies[j].v == bodies[i].v) {
        owner[i] = owner[j];
        break;
      }
    }
    body_holds[i] = body_slides[i] = true;
  }
  for (std::size_t i = 0; i < N; ++i) {
    body_holds[owner[i]] = body_holds[owner[i]] && holds[i];
    body_slides[owner[i]] = body_slides[owner[i]] && slides[i];
  }

  // Else projected Gauss-Seidel, warm-started from the last step's impulses
  // where the contact stays closed: the first half of the sweeps with the
  // static limit where the contact stuck at the last step, then those it
  // cannot hold slide under the kinetic one (broken loose within the step).
  std::array<Vec3, N> impulse;
  for (std::size_t i = 0; i < N; ++i) {
    const ContactPoint& c = data[i];
    impulse[i] = active[i] * h *
                 Vec3(out.normal[i], c.tangent1.dot(out.tangential[i]), c.tangent2.dot(out.tangential[i]));
    contact_detail::apply_impulse(c, bodies[i], frame[i], impulse[i]);
  }
  std::array<double, N> stuck{};
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    if (sweep == sweeps / 2) {
      // Those that slide start the kinetic half at the kinetic limit against
      // the friction that would have held them (the stick trial's): the
      // direction the loads drive them in, where the static half's friction
      // carries directions from stopping the body sweep by sweep.
      for (std::size_t i = 0; i < N; ++i) {
        if (stuck[i] > 0.0) continue;
        limit_factor[i] = data[i].mu_kinetic;
        const Eigen::Vector2d hold = held[i].template tail<2>();
        const Eigen::Vector2d start = data[i].mu_kinetic * impulse[i][0] / std::max(hold.norm(), 1e-300) * hold;
        contact_detail::apply_impulse(data[i], bodies[i], frame[i],
                                      Vec3(0.0, start[0] - impulse[i][1], start[1] - impulse[i][2]));
        impulse[i].template tail<2>() = start;
      }
    }
    const bool kinetic_phase = sweep >= sweeps / 2;
    for (std::size_t i = 0; i < N; ++i) {
      const ContactPoint& c = data[i];
      const Frame& f = frame[i];
      Vec3 u = contact_detail::point_velocity(c, bodies[i], f);
      Vec3 p = impulse[i];
      // Normal: the approach speed to its target, pushing only.
      p[0] = active[i] * std::max(0.0, p[0] - (u[0] - normal_target[i]) / block[i](0, 0));
      u += block[i].col(0) * (p[0] - impulse[i][0]);
      // Tangential: the impulse that stops the slip, if the friction cone holds it.
      const Eigen::Vector2d trial = p.tail<2>() - tangent_inverse[i] * u.tail<2>();
      const double limit = limit_factor[i] * p[0];
      const bool sticks = trial.norm() <= limit;
      // Else the limit: in the static half projected onto the cone, in the
      // kinetic half against the slip velocity (with this contact's impulse
      // so far), which the sweeps bring to the end-of-step slip (maximum
      // dissipation).
      const Eigen::Vector2d slip =
          kinetic_phase && u.tail<2>().squaredNorm() > 0.0 ? Eigen::Vector2d(-u.tail<2>()) : trial;
      p.tail<2>() = sticks ? trial : Eigen::Vector2d(limit / std::max(slip.norm(), 1e-300) * slip);
      stuck[i] = sticks && p[0] > 0.0 ? 1.0 : 0.0;
      contact_detail::apply_impulse(c, bodies[i], f, p - impulse[i]);
      impulse[i] = p;
    }
  }
  // A trial's impulses instead, on the bodies it holds for.
  for (std::size_t i = 0; i < N; ++i) {
    if (!body_holds[owner[i]] && !body_slides[owner[i]]) continue;
    *bodies[i].v = start_v[i];
    if (bodies[i].w) *bodies[i].w = start_w[i];
  }
  for (std::size_t i = 0; i < N; ++i) {
    const bool hold = body_holds[owner[i]];
    if (!hold && !body_slides[owner[i]]) continue;
    impulse[i] = hold ? held[i] : slid[i];
    stuck[i] = hold && held[i][0] > 0.0 ? active[i] : 0.0;
    contact_detail::apply_impulse(data[i], bodies[i], frame[i], impulse[i]);
  }

  // Positions: the impulses as a constant force over the step, h/2 of the
  // velocity change, summed per body and turned once (rotations from
  // several contacts applied one after another would not commute, and a
  // body held still would creep).
  std::array<Vec3, N> shift, turn;
  for (std::size_t i = 0; i < N; ++i) {
    const std::size_t first = owner[i];  // the body's first contact holds its sums
    const Vec3 p = (0.5 * h) * impulse[i];
    const Vec3 dr = data[i].inverse_mass * (p[0] * data[i].normal + p[1] * data[i].tangent1 + p[2] * data[i].tangent2);
    const Vec3 dtheta = data[i].inverse_inertia * (p[0] * frame[i].arm[0] + p[1] * frame[i].arm[1] + p[2] * frame[i].arm[2]);
    shift[i] = turn[i] = Vec3::Zero();
    shift[first] += dr;
    turn[first] += dtheta;
  }
  for (std::size_t i = 0; i < N; ++i) {
    *bodies[i].r += shift[i];
    if (bodies[i].p) *bodies[i].p = quaternion_product(*bodies[i].p, cayley_increment(turn[i]));
    out.normal[i] = impulse[i][0] / h;
    out.tangential[i] = (impulse[i][1] * data[i].tangent1 + impulse[i][2] * data[i].tangent2) / h;
    out.stuck[i] = stuck[i];
  }
  // Penetration an impact left: projected out along the normals (one pass
  // per sweep, pushing only).
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    for (std::size_t i = 0; i < N; ++i) {
      const Frame f = contact_detail::frame_of(data[i], bodies[i]);
      const double push = std::max(0.0, -f.gap / block[i](0, 0));
      contact_detail::displace(data[i], bodies[i], f, Vec3(push, 0.0, 0.0));
    }
  }
}

// Whether a generated model has contacts (it then defines M::kContacts).
template <class M, class = void>
struct has_contacts : std::false_type {};
template <class M>
struct has_contacts<M, std::void_t<decltype(M::kContacts)>> : std::true_type {};

// A generated model's contacts after its smooth step from `start` (read
// only) to s: its data, its bodies' state and the State's contact fields;
// nothing for a model without contacts.
template <class M>
void contact_step(typename M::State& start, typename M::State& s) noexcept {
  if constexpr (has_contacts<M>::value) {
    constexpr std::size_t n = static_cast<std::size_t>(M::kContacts);
    const std::array<ContactBody, n> before = M::contact_bodies(start);
    std::array<double, n> start_normal_velocity;
    for (std::size_t i = 0; i < n; ++i) {
      const contact_detail::Frame f = contact_detail::frame_of(M::kContactPoints[i], before[i]);
      start_normal_velocity[i] = contact_detail::point_velocity(M::kContactPoints[i], before[i], f)[0];
    }
    resolve_contacts<n>(M::kContactPoints, M::contact_bodies(s), M::kStep, M::kContactSweeps, M::kBounceSpeed,
                        start_normal_velocity, {s.contact_normal, s.contact_tangential, s.contact_stuck});
  }
}

// The initial state's contacts: stuck where the point touches the plane
// (within 1e-9 m) without sliding, so a body set down at rest starts held
// by static friction.
template <class M>
void start_contacts(typename M::State& s) noexcept {
  const auto bodies = M::contact_bodies(s);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const ContactPoint& c = M::kContactPoints[i];
    const contact_detail::Frame f = contact_detail::frame_of(c, bodies[i]);
    const Vec3 u = contact_detail::point_velocity(c, bodies[i], f);
    s.contact_stuck[i] = f.gap <= 1e-9 && u[1] == 0.0 && u[2] == 0.0 ? 1.0 : 0.0;
    s.contact_normal[i] = 0.0;
    s.contact_tangential[i].setZero();  // Eigen leaves it unset
  }
}

}  // namespace mbrt
