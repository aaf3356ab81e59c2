// Unilateral frictional contacts of bodies with fixed planes
// (docs/contact.md). After the scheme's smooth step, velocity-level impulses
// (Moreau 1988, "Unilateral contact and dry friction in finite freedom
// dynamics"; Stewart 2000, "Rigid-body dynamics with friction and impact",
// SIAM Review 42(1)) make every touching contact push, never pull, and
// either stick or slide under Coulomb friction: a contact stuck at the last
// step holds up to mu_static times its normal impulse, a sliding one feels
// mu_kinetic. Per mechanism (a free body, or bodies joined by joints, whose
// joints take their share of each impulse), the stick trial, else the slide trial
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

#include "mbrt/flag.hpp"
#include "mbrt/contact_geometry.hpp"
#include "mbrt/contact_trials.hpp"
#include "mbrt/mechanism_response.hpp"

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

// Projected Gauss-Seidel over one mechanism's contacts, in contact
// velocities u = u0 + K P (K full: both triangles), from the last step's
// impulses (where the contact stays closed), for the mechanisms neither
// trial holds for: the first half of the sweeps with the static limit where
// the contact stuck at the last step, then those it cannot hold slide under
// the kinetic one (broken loose within the step), starting at the kinetic
// limit along the stick trial's friction (the way the loads drive them; the
// static half's friction carries directions from stopping the body sweep by
// sweep). Each contact's normal impulse and its stick impulse on its own 3x3
// block of K; a sliding contact's friction against its slip velocity, which
// the sweeps bring to the end-of-step slip (maximum dissipation).
template <std::size_t N, std::size_t G>
void gauss_seidel(const std::array<ContactPoint, N>& data, const Eigen::Matrix<double, 3 * int(G), 3 * int(G)>& k,
                  const ContactGroup<G>& group, double h, int sweeps, const ContactProblem<N>& problem,
                  const std::array<Vec3, N>& held, const ContactForces<N>& last, std::array<Vec3, N>& impulse,
                  std::array<double, N>& stuck) noexcept {
  constexpr int n = 3 * static_cast<int>(G);
  const int used = members(group);
  std::array<Eigen::Matrix2d, G> tangent_inverse;
  std::array<double, G> limit_factor{};
  Eigen::Matrix<double, n, 1> p = Eigen::Matrix<double, n, 1>::Zero(), u0 = Eigen::Matrix<double, n, 1>::Zero();
  for (int l = 0; l < used; ++l) {
    const std::size_t i = static_cast<std::size_t>(group[static_cast<std::size_t>(l)]);
    // The tangential block's inverse, shifted by 1e-10 of its trace as the
    // exact solves are (least_norm_solve): a joint that locks a tangent (a
    // pinned rod's tip along the rod) leaves the block singular.
    const Mat3 d = k.template block<3, 3>(3 * l, 3 * l);
    const double shift = 1e-10 * (d(1, 1) + d(2, 2)) + 1e-300;
    const double det = (d(1, 1) + shift) * (d(2, 2) + shift) - d(1, 2) * d(2, 1);
    tangent_inverse[static_cast<std::size_t>(l)] << (d(2, 2) + shift) / det, -d(1, 2) / det, -d(2, 1) / det, (d(1, 1) + shift) / det;
    limit_factor[static_cast<std::size_t>(l)] = problem.limit_factor[i];
    p.template segment<3>(3 * l) = problem.active[i] * h *
                                   Vec3(last.normal[i], data[i].tangent1.dot(last.tangential[i]), data[i].tangent2.dot(last.tangential[i]));
    u0.template segment<3>(3 * l) = problem.start_velocity[i];
    stuck[i] = 0.0;
  }
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    const bool kinetic_half = sweep >= sweeps / 2;
    if (sweep == sweeps / 2) {
      for (int l = 0; l < used; ++l) {
        const std::size_t i = static_cast<std::size_t>(group[static_cast<std::size_t>(l)]);
        const double keep = stuck[i];  // 1 stays, 0 switches (arithmetic: the same work either way)
        double& factor = limit_factor[static_cast<std::size_t>(l)];
        factor = keep * factor + (1.0 - keep) * data[i].mu_kinetic;
        const Eigen::Vector2d hold = held[i].template tail<2>();
        const Eigen::Vector2d start = data[i].mu_kinetic * p[3 * l] / at_least(hold.norm(), 1e-300) * hold;
        p.template segment<2>(3 * l + 1) += (1.0 - keep) * (start - p.template segment<2>(3 * l + 1));
      }
    }
    for (int l = 0; l < used; ++l) {
      const std::size_t i = static_cast<std::size_t>(group[static_cast<std::size_t>(l)]);
      const auto block = k.template block<3, 3>(3 * l, 3 * l);
      const Vec3 old = p.template segment<3>(3 * l);
      Vec3 u = u0.template segment<3>(3 * l) + k.template middleRows<3>(3 * l) * p;  // its velocity now
      Vec3 q = old;
      // Normal: the approach speed to its target, pushing only.
      q[0] = problem.active[i] * positive_part(q[0] - (u[0] - problem.target[i]) / (block(0, 0) * (1.0 + 1e-10) + 1e-300));
      u += block.col(0) * (q[0] - old[0]);
      // Tangential: the impulse that stops the slip, if the friction cone holds it.
      const Eigen::Vector2d trial = q.template tail<2>() - tangent_inverse[static_cast<std::size_t>(l)] * u.template tail<2>();
      const double limit = limit_factor[static_cast<std::size_t>(l)] * q[0];
      const bool holds = trial.norm() <= limit;
      const double sticks = flag(holds);
      // Both candidates computed and blended by 0/1 weights, not picked by a
      // branch: the same instructions whatever sticks or slides.
      const Eigen::Vector2d against_slip = -u.template tail<2>();
      const double by_slip = flag(kinetic_half & (against_slip.squaredNorm() > 0.0));
      const Eigen::Vector2d slip = by_slip * against_slip + (1.0 - by_slip) * trial;
      const Eigen::Vector2d at_limit = limit / at_least(slip.norm(), 1e-300) * slip;
      q.template tail<2>() = sticks * trial + (1.0 - sticks) * at_limit;
      // From the two conditions' bits (mbrt/flag.hpp), not `sticks * (q[0] > 0)`.
      stuck[i] = flag(holds & (q[0] > 0.0));
      p.template segment<3>(3 * l) = q;
    }
  }
  for (int l = 0; l < used; ++l) impulse[static_cast<std::size_t>(group[static_cast<std::size_t>(l)])] = p.template segment<3>(3 * l);
}

// K of a mechanism with joints: the free part (delassus_matrix) plus, per
// column (a contact's unit impulse), what the joints take back: the
// constrained response's point velocities at the mechanism's contacts.
// compliance: each contact's normal row of K with the joints, closed or not
// (the penetration projection's).
template <class M, std::size_t N, std::size_t G>
void add_joints(const std::array<ContactPoint, N>& data, const ContactProblem<N>& p, const ContactGroup<G>& group,
                int group_index, const Joints<M>& joints, Eigen::Matrix<double, 3 * int(G), 3 * int(G)>& k,
                std::array<double, N>& compliance) noexcept {
  const int used = members(group);
  for (int lj = 0; lj < used; ++lj) {
    const std::size_t j = static_cast<std::size_t>(group[static_cast<std::size_t>(lj)]);
    for (int b = 0; b < 3; ++b) {
      typename M::BodyVectors x;
      for (Vec6& e : x) e.setZero();
      const Vec6 free = body_response(data[j], p.frame[j], Vec3::Unit(b));
      x[static_cast<std::size_t>(data[j].body)] = free;
      joints.constrain(x, group_index);
      x[static_cast<std::size_t>(data[j].body)] -= free;  // the joints' share alone
      for (int li = lj; li < used; ++li) {
        const std::size_t i = static_cast<std::size_t>(group[static_cast<std::size_t>(li)]);
        const Vec3 u = point_velocity_of(data[i], p.frame[i], x[static_cast<std::size_t>(data[i].body)]);
        k.template block<3, 1>(3 * li, 3 * lj + b) += (p.active[i] * p.active[j]) * u;
        if (li == lj && b == 0) compliance[j] = delassus_block(data[j], p.frame[j])(0, 0) + u[0];
      }
    }
  }
}

// A step's contact problem: each contact's body, geometry, velocity after
// the smooth step and what it must reach (contact_trials.hpp), from the
// contact point's normal velocity at the step's start and the last step's
// stick states (out). M::kBounceSpeed: the approach speed below which a
// contact does not bounce (so a body at rest settles instead of chattering).
template <class M>
struct ContactSetup {
  static constexpr std::size_t N = static_cast<std::size_t>(M::kContacts);
  std::array<ContactBody, N> bodies;
  ContactProblem<N> problem;
};

// Each contact's normal velocity at the step's start (its restitution's
// reference), from the start's bodies.
template <class M>
std::array<double, M::kContacts> start_normal_velocities(typename M::State& start) noexcept {
  constexpr std::size_t n = static_cast<std::size_t>(M::kContacts);
  const std::array<ContactBody, n> before = M::contact_bodies(start);
  std::array<double, n> velocity;
  for (std::size_t i = 0; i < n; ++i) {
    const Frame f = frame_of(M::kContactPoints[i], before[i]);
    velocity[i] = point_velocity(M::kContactPoints[i], before[i], f)[0];
  }
  return velocity;
}

template <class M>
ContactSetup<M> contact_setup(typename M::State& s, const ContactForces<M::kContacts>& out,
                              const std::array<double, M::kContacts>& start_normal_velocity) noexcept {
  constexpr std::size_t N = static_cast<std::size_t>(M::kContacts);
  ContactSetup<M> setup{M::contact_bodies(s), {}};
  ContactProblem<N>& problem = setup.problem;
  for (std::size_t i = 0; i < N; ++i) {
    const ContactPoint& c = M::kContactPoints[i];
    problem.frame[i] = frame_of(c, setup.bodies[i]);
    problem.active[i] = flag(problem.frame[i].gap <= 0.0);
    const Vec3 u = point_velocity(c, setup.bodies[i], problem.frame[i]);
    problem.start_velocity[i] = u;
    // A bounce (Newton's law, separation = e approach) at the approach speed
    // averaged over the step, less the smooth loads' half step after it: the
    // impact's instant within the step is unknown, and this is the
    // end-of-step speed averaged over it, which leaves bounce heights unbiased.
    const double average = 0.5 * (start_normal_velocity[i] + u[0]);
    const double bounce = -c.restitution * average + 0.5 * (u[0] - start_normal_velocity[i]);
    const double target = flag(u[0] < -M::kBounceSpeed) * positive_part(bounce);
    problem.target[i] = target;
    problem.to_reach[i] = Vec3(target, 0.0, 0.0) - u;
    const double was_stuck = flag(out.stuck[i] > 0.0);
    problem.limit_factor[i] = was_stuck * c.mu_static + (1.0 - was_stuck) * c.mu_kinetic;
  }
  return setup;
}

// One mechanism's K (M::kContactGroups index g), both triangles, with its
// joints' share where its bodies are in joints; compliance: see add_joints.
template <class M, std::size_t G>
Eigen::Matrix<double, 3 * int(G), 3 * int(G)> group_matrix(const ContactProblem<M::kContacts>& problem,
                                                            const ContactGroup<G>& group, int g, const Joints<M>& joints,
                                                            std::array<double, M::kContacts>& compliance) noexcept {
  auto k = delassus_matrix(M::kContactPoints, problem, group);
  if constexpr (M::kJointedContacts) {
    if (M::kContactPoints[static_cast<std::size_t>(group[0])].jointed) add_joints(M::kContactPoints, problem, group, g, joints, k, compliance);
  }
  for (int r = 0; r < k.rows(); ++r) {  // both triangles, for Gauss-Seidel's rows
    for (int c = r + 1; c < k.cols(); ++c) k(r, c) = k(c, r);
  }
  return k;
}

// One mechanism's impulses and stick states: the stick trial's where it
// holds, else the slide trial's where that holds, else Gauss-Seidel's
// (picked by index: the same work whatever is picked).
template <class M, std::size_t G>
void solve_group(const Eigen::Matrix<double, 3 * int(G), 3 * int(G)>& k, const ContactProblem<M::kContacts>& problem,
                 const ContactGroup<G>& group, const ContactForces<M::kContacts>& last,
                 std::array<Vec3, M::kContacts>& impulse, std::array<double, M::kContacts>& stuck) noexcept {
  constexpr std::size_t N = static_cast<std::size_t>(M::kContacts);
  std::array<Vec3, N> held, slid, swept;
  std::array<double, N> swept_stuck;
  const bool holds = stick_trial(k, problem, group, held);
  const bool slides = slide_trial(M::kContactPoints, k, problem, group, held, slid);
  gauss_seidel(M::kContactPoints, k, group, M::kStep, M::kContactSweeps, problem, held, last, swept, swept_stuck);
  const int pick = (1 - static_cast<int>(holds)) * (2 - static_cast<int>(slides));  // 0, 1 or 2
  for (int l = 0; l < members(group); ++l) {
    const std::size_t i = static_cast<std::size_t>(group[static_cast<std::size_t>(l)]);
    const std::array<const Vec3*, 3> options{&held[i], &slid[i], &swept[i]};
    const std::array<double, 3> stuck_options{flag(held[i][0] > 0.0) * problem.active[i], 0.0, swept_stuck[i]};
    impulse[i] = *options[static_cast<std::size_t>(pick)];
    stuck[i] = stuck_options[static_cast<std::size_t>(pick)];
  }
}

// Every body's velocity change at once, with its joints' share; positions
// take the impulses as a force constant over the step, h/2 of the velocity
// change (a body's rotations from several contacts summed and turned once:
// turned one after another they would not commute, and a body held still
// would creep). Then out, and the penetration an impact left projected out
// along the normals, pushing only, contact by contact in two passes (a
// body is rarely left inside the plane at more than two contacts at once; a
// resting one is not left inside at all); a jointed body's mechanism moves
// with it. Returns the joints' share of the impulses as forces, z / h.
template <class M>
typename M::Rows apply_impulses(typename M::State& s, const Joints<M>& joints, const ContactSetup<M>& setup,
                                const std::array<Vec3, M::kContacts>& impulse, const std::array<double, M::kContacts>& stuck,
                                const std::array<double, M::kContacts>& compliance,
                                const std::array<int, M::kContacts>& group_of, const ContactForces<M::kContacts>& out) noexcept {
  constexpr std::size_t N = static_cast<std::size_t>(M::kContacts);
  constexpr double h = M::kStep;
  const std::array<ContactPoint, N>& data = M::kContactPoints;
  typename M::BodyVectors change;
  for (Vec6& e : change) e.setZero();
  for (std::size_t i = 0; i < N; ++i) {
    change[static_cast<std::size_t>(data[i].body)] += body_response(data[i], setup.problem.frame[i], impulse[i]);
  }
  typename M::Rows joint_forces = M::Rows::Zero();
  if constexpr (M::kJointedContacts) joint_forces = joints.constrain(change) / h;
  typename M::BodyVectors u = M::generalized_velocities(s);
  for (std::size_t b = 0; b < u.size(); ++b) {
    u[b] += change[b];
    change[b] *= 0.5 * h;
  }
  M::set_velocities(u, s);
  M::displace(change, s);
  for (std::size_t i = 0; i < N; ++i) {
    out.normal[i] = impulse[i][0] / h;
    out.tangential[i] = (impulse[i][1] * data[i].tangent1 + impulse[i][2] * data[i].tangent2) / h;
    out.stuck[i] = stuck[i];
  }
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t i = 0; i < N; ++i) {
      const Frame f = frame_of(data[i], setup.bodies[i]);
      if constexpr (M::kJointedContacts) {
        if (data[i].jointed) {  // constant per contact: the same work every step
          const Vec3 push(positive_part(-f.gap / compliance[i]), 0.0, 0.0);
          typename M::BodyVectors shift;
          for (Vec6& e : shift) e.setZero();
          shift[static_cast<std::size_t>(data[i].body)] = body_response(data[i], f, push);
          joints.constrain(shift, group_of[i]);
          M::displace(shift, s);
          continue;
        }
      }
      const Vec3 push(positive_part(-f.gap / delassus_block(data[i], f)(0, 0)), 0.0, 0.0);
      displace(data[i], setup.bodies[i], f, push);
    }
  }
  return joint_forces;
}

}  // namespace contact_detail

// (positions and velocities after the smooth step; out: the last step's
// forces and stick states; each contact point's normal velocity at the
// step's start) => (positions, velocities, out; returns the joints' share
// of the impulses as forces, z / h, zero without jointed contacts). Per
// mechanism (M::kContactGroups): K, then the stick trial, else the slide
// trial, else Gauss-Seidel with M::kContactSweeps sweeps; then
// contact_detail::apply_impulses.
template <class M>
typename M::Rows resolve_contacts(typename M::State& s, const Joints<M>& joints,
                                  const std::array<double, M::kContacts>& start_normal_velocity) noexcept {
  constexpr std::size_t N = static_cast<std::size_t>(M::kContacts);
  const ContactForces<N> out{s.contact_normal, s.contact_tangential, s.contact_stuck};
  const contact_detail::ContactSetup<M> setup = contact_detail::contact_setup<M>(s, out, start_normal_velocity);
  std::array<Vec3, N> impulse;
  std::array<double, N> stuck, compliance{};
  std::array<int, N> group_of{};  // each contact's M::kContactGroups index
  for (std::size_t g = 0; g < M::kContactGroups.size(); ++g) {
    const auto& group = M::kContactGroups[g];
    for (int l = 0; l < contact_detail::members(group); ++l) group_of[static_cast<std::size_t>(group[static_cast<std::size_t>(l)])] = static_cast<int>(g);
    const auto k = contact_detail::group_matrix<M>(setup.problem, group, static_cast<int>(g), joints, compliance);
    contact_detail::solve_group<M>(k, setup.problem, group, out, impulse, stuck);
  }
  return contact_detail::apply_impulses<M>(s, joints, setup, impulse, stuck, compliance, group_of, out);
}

// Whether a generated model has contacts (it then defines M::kContacts).
template <class M, class = void>
struct has_contacts : std::false_type {};
template <class M>
struct has_contacts<M, std::void_t<decltype(M::kContacts)>> : std::true_type {};

// Whether a contact's body is in a joint or driver (its impulses then need
// the scheme's factor of S).
template <class M>
constexpr bool jointed_contacts() noexcept {
  if constexpr (has_contacts<M>::value) return M::kJointedContacts;
  else return false;
}

// A generated model's contacts after its smooth step from `start` (read
// only) to s; c: the scheme's constraint system at s, factorized (needed
// where a contact's body is in a joint, M::kJointedContacts; then returns
// the joints' share of the impulses as forces). Nothing for a model without
// contacts.
template <class M>
typename M::Rows contact_step(typename M::State& start, typename M::State& s,
                              const typename M::ConstraintSystem* c = nullptr) noexcept {
  if constexpr (has_contacts<M>::value) {
    return resolve_contacts<M>(s, Joints<M>{c}, contact_detail::start_normal_velocities<M>(start));
  } else {
    (void)start, (void)s, (void)c;
    return M::Rows::Zero();
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
