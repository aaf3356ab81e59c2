// Unilateral frictional contacts of free bodies with fixed planes
// (docs/contact.md). After the scheme's smooth step, velocity-level impulses
// (Moreau 1988, "Unilateral contact and dry friction in finite freedom
// dynamics"; Stewart 2000, "Rigid-body dynamics with friction and impact",
// SIAM Review 42(1)) make every touching contact push, never pull, and
// either stick or slide under Coulomb friction: a contact stuck at the last
// step holds up to mu_static times its normal impulse, a sliding one feels
// mu_kinetic. Per body, the stick trial, else the slide trial
// (include/mbrt/contact_trials.hpp), else projected Gauss-Seidel with a
// fixed number of sweeps; positions take the impulses as a force constant
// over the step (h/2 of the velocity change), then penetration an impact
// left is projected out along the normals. Fixed work whatever touches,
// sticks or slides; nothing allocated.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <type_traits>

#include "mbrt/contact_geometry.hpp"
#include "mbrt/contact_trials.hpp"

namespace mbrt {

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

// Projected Gauss-Seidel over all contacts from the last step's impulses
// (where the contact stays closed), for the bodies neither trial holds for:
// the first half of the sweeps with the static limit where the contact
// stuck at the last step, then those it cannot hold slide under the kinetic
// one (broken loose within the step), starting at the kinetic limit along
// the stick trial's friction (the way the loads drive them; the static
// half's friction carries directions from stopping the body sweep by sweep).
// Each contact's normal impulse and its stick impulse on its own 3x3 block
// of K; a sliding contact's friction against its slip velocity, which the
// sweeps bring to the end-of-step slip (maximum dissipation).
template <std::size_t N>
void gauss_seidel(const std::array<ContactPoint, N>& data, const std::array<ContactBody, N>& bodies, double h,
                  int sweeps, const ContactProblem<N>& problem, const std::array<Vec3, N>& held,
                  const ContactForces<N>& last, std::array<Vec3, N>& impulse, std::array<double, N>& stuck) noexcept {
  std::array<Mat3, N> block;
  std::array<Eigen::Matrix2d, N> tangent_inverse;
  std::array<double, N> limit_factor = problem.limit_factor;
  for (std::size_t i = 0; i < N; ++i) {
    const ContactPoint& c = data[i];
    block[i] = delassus_block(c, problem.frame[i]);
    const Mat3& d = block[i];
    const double det = d(1, 1) * d(2, 2) - d(1, 2) * d(2, 1);
    tangent_inverse[i] << d(2, 2) / det, -d(1, 2) / det, -d(2, 1) / det, d(1, 1) / det;
    impulse[i] = problem.active[i] * h *
                 Vec3(last.normal[i], c.tangent1.dot(last.tangential[i]), c.tangent2.dot(last.tangential[i]));
    apply_impulse(c, bodies[i], problem.frame[i], impulse[i]);
    stuck[i] = 0.0;
  }
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    const bool kinetic_half = sweep >= sweeps / 2;
    if (sweep == sweeps / 2) {
      for (std::size_t i = 0; i < N; ++i) {
        const double keep = stuck[i];  // 1 stays, 0 switches (arithmetic: the same work either way)
        limit_factor[i] = keep * limit_factor[i] + (1.0 - keep) * data[i].mu_kinetic;
        const Eigen::Vector2d hold = held[i].template tail<2>();
        const Eigen::Vector2d start = data[i].mu_kinetic * impulse[i][0] / at_least(hold.norm(), 1e-300) * hold;
        const Eigen::Vector2d change = (1.0 - keep) * (start - impulse[i].template tail<2>());
        apply_impulse(data[i], bodies[i], problem.frame[i], Vec3(0.0, change[0], change[1]));
        impulse[i].template tail<2>() += change;
      }
    }
    for (std::size_t i = 0; i < N; ++i) {
      const ContactPoint& c = data[i];
      const Frame& f = problem.frame[i];
      Vec3 u = point_velocity(c, bodies[i], f);
      Vec3 p = impulse[i];
      // Normal: the approach speed to its target, pushing only.
      p[0] = problem.active[i] * positive_part(p[0] - (u[0] - problem.target[i]) / block[i](0, 0));
      u += block[i].col(0) * (p[0] - impulse[i][0]);
      // Tangential: the impulse that stops the slip, if the friction cone holds it.
      const Eigen::Vector2d trial = p.template tail<2>() - tangent_inverse[i] * u.template tail<2>();
      const double limit = limit_factor[i] * p[0];
      const double sticks = static_cast<double>(trial.norm() <= limit);
      // Both candidates computed and blended by 0/1 weights, not picked by a
      // branch: the same instructions whatever sticks or slides.
      const Eigen::Vector2d against_slip = -u.template tail<2>();
      const double by_slip = static_cast<double>(kinetic_half & (against_slip.squaredNorm() > 0.0));
      const Eigen::Vector2d slip = by_slip * against_slip + (1.0 - by_slip) * trial;
      const Eigen::Vector2d at_limit = limit / at_least(slip.norm(), 1e-300) * slip;
      p.template tail<2>() = sticks * trial + (1.0 - sticks) * at_limit;
      stuck[i] = sticks * static_cast<double>(p[0] > 0.0);
      apply_impulse(c, bodies[i], f, p - impulse[i]);
      impulse[i] = p;
    }
  }
}

}  // namespace contact_detail

// (positions and velocities after the smooth step; out: the last step's
// forces and stick states; each contact point's normal velocity at the
// step's start) => (positions, velocities, out). groups: each body's
// contacts; h: the step; sweeps: Gauss-Seidel sweeps (fixed at generation);
// bounce_speed: the approach speed below which a contact does not bounce
// (so a body at rest settles instead of chattering).
template <std::size_t N, std::size_t G, std::size_t B>
void resolve_contacts(const std::array<ContactPoint, N>& data, const std::array<ContactBody, N>& bodies,
                      const std::array<ContactGroup<G>, B>& groups, double h, int sweeps, double bounce_speed,
                      const std::array<double, N>& start_normal_velocity, ContactForces<N> out) noexcept {
  ContactProblem<N> problem;
  std::array<Vec3, N> start_v, start_w;  // the bodies' velocities after the smooth step
  for (std::size_t i = 0; i < N; ++i) {
    const ContactPoint& c = data[i];
    problem.frame[i] = contact_detail::frame_of(c, bodies[i]);
    problem.active[i] = static_cast<double>(problem.frame[i].gap <= 0.0);
    const Vec3 u = contact_detail::point_velocity(c, bodies[i], problem.frame[i]);
    // A bounce (Newton's law, separation = e approach) at the approach speed
    // averaged over the step, less the smooth loads' half step after it: the
    // impact's instant within the step is unknown, and this is the
    // end-of-step speed averaged over it, which leaves bounce heights unbiased.
    const double average = 0.5 * (start_normal_velocity[i] + u[0]);
    const double bounce = -c.restitution * average + 0.5 * (u[0] - start_normal_velocity[i]);
    const double target = static_cast<double>(u[0] < -bounce_speed) * contact_detail::positive_part(bounce);
    problem.target[i] = target;
    problem.to_reach[i] = Vec3(target, 0.0, 0.0) - u;
    const double was_stuck = static_cast<double>(out.stuck[i] > 0.0);
    problem.limit_factor[i] = was_stuck * c.mu_static + (1.0 - was_stuck) * c.mu_kinetic;
    start_v[i] = *bodies[i].v;
    start_w[i] = bodies[i].w ? *bodies[i].w : Vec3(Vec3::Zero());
  }
  // The trials, body by body.
  std::array<Vec3, N> held, slid;
  std::array<bool, B> holds, slides;
  for (std::size_t g = 0; g < B; ++g) {
    const auto k = contact_detail::delassus_matrix(data, problem, groups[g]);
    holds[g] = stick_trial(k, problem, groups[g], held);
    slides[g] = slide_trial(data, k, problem, groups[g], held, slid);
  }
  std::array<Vec3, N> impulse;
  std::array<double, N> stuck;
  contact_detail::gauss_seidel(data, bodies, h, sweeps, problem, held, out, impulse, stuck);
  // Each body's impulses: the stick trial's where it holds, else the slide
  // trial's where that holds, else Gauss-Seidel's; its velocities from the
  // smooth step's and them (picked by index: the same work whatever is picked).
  for (std::size_t g = 0; g < B; ++g) {
    const int pick = (1 - static_cast<int>(holds[g])) * (2 - static_cast<int>(slides[g]));  // 0, 1 or 2
    for (const int member : groups[g]) {
      if (member < 0) continue;
      const std::size_t i = static_cast<std::size_t>(member);
      *bodies[i].v = start_v[i];
      if (bodies[i].w) *bodies[i].w = start_w[i];
    }
    for (const int member : groups[g]) {
      if (member < 0) continue;
      const std::size_t i = static_cast<std::size_t>(member);
      const std::array<const Vec3*, 3> options{&held[i], &slid[i], &impulse[i]};
      const std::array<double, 3> stuck_options{static_cast<double>(held[i][0] > 0.0) * problem.active[i], 0.0, stuck[i]};
      impulse[i] = *options[static_cast<std::size_t>(pick)];
      stuck[i] = stuck_options[static_cast<std::size_t>(pick)];
      contact_detail::apply_impulse(data[i], bodies[i], problem.frame[i], impulse[i]);
    }
  }

  // Positions: the impulses as a force constant over the step, h/2 of the
  // velocity change, summed per body and turned once (rotations from
  // several contacts applied one after another would not commute, and a
  // body held still would creep).
  for (const ContactGroup<G>& group : groups) {
    Vec3 shift = Vec3::Zero(), turn = Vec3::Zero();
    for (const int member : group) {
      if (member < 0) continue;
      const std::size_t i = static_cast<std::size_t>(member);
      const Vec3 p = (0.5 * h) * impulse[i];
      shift += contact_detail::linear_response(data[i], p);
      turn += contact_detail::angular_response(data[i], problem.frame[i], p);
    }
    const ContactBody& body = bodies[static_cast<std::size_t>(group[0])];
    *body.r += shift;
    if (body.p) *body.p = quaternion_product(*body.p, cayley_increment(turn));
  }
  for (std::size_t i = 0; i < N; ++i) {
    out.normal[i] = impulse[i][0] / h;
    out.tangential[i] = (impulse[i][1] * data[i].tangent1 + impulse[i][2] * data[i].tangent2) / h;
    out.stuck[i] = stuck[i];
  }
  // Penetration an impact left: projected out along the normals, pushing
  // only, in two passes (a body is rarely left inside the plane at more
  // than two contacts at once; a resting one is not left inside at all).
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t i = 0; i < N; ++i) {
      const contact_detail::Frame f = contact_detail::frame_of(data[i], bodies[i]);
      const double push = contact_detail::positive_part(-f.gap / contact_detail::delassus_block(data[i], f)(0, 0));
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
    resolve_contacts(M::kContactPoints, M::contact_bodies(s), M::kContactGroups, M::kStep, M::kContactSweeps,
                     M::kBounceSpeed, start_normal_velocity, {s.contact_normal, s.contact_tangential, s.contact_stuck});
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
