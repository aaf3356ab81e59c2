// The step of the schemes built on the two-stage staggered explicit-implicit
// integrator (Park & Chiou 1988, "Stabilization of computational procedures
// for constrained dynamical systems", J. Guidance 11(4); docs/staggered-pcst.md):
// staggered-pcst, staggered-nps, baumgarte and blajer.
//
// M is a generated model (struct Model in the model's source, spatial or
// planar coordinates). It provides
//   types     State, Workspace, Rows, BodyVectors;
//   constants kScheme, kStep, kStages (implicit passes), kPositionStage,
//             kPositionIterations, kCorrections (blajer);
//   kernels   kinematics, velocities_of, generalized_velocities, set_velocities,
//             accelerations_of, applied_loads, free_accelerations, kick, drift,
//             constraint_rows, constraint_directions, factorize, solve,
//             stacked_phi, velocity_residual, subtract_constraint_forces,
//             constraint_forces; with the position stage factorize_newton and
//             solve_newton; staggered-nps factorize_tree, factorize_cut and its
//             implicit_stage; blajer correct_positions.
// Workspace holds what one step works on: last_good (State), k (kinematics),
// c (constraint system at t + h), c0 (at t, position stage), g (Newton matrix,
// position stage), t (tree system, staggered-nps) and l (loads).
#pragma once

#include <type_traits>
#include <utility>

#include "mbrt/contacts.hpp"
#include "mbrt/scheme.hpp"
#include "mbrt/schemes/contacts_with_joint_friction.hpp"
#include "mbrt/schemes/joint_friction_absolute.hpp"
#include "mbrt/schemes/state_checks.hpp"
#include "mbrt/step_status.hpp"

namespace mbrt::schemes {

// The kernels that form M^-1 (staggered-nps: M's tree elimination). Where masses are runtime parameters
// (docs/parameters.md) the model's take the state, which holds them; the
// traits below tell the two forms apart (C++17: generated models build with it).
template <class M, class = void>
struct directions_read_state : std::false_type {};
template <class M>
struct directions_read_state<M, std::void_t<decltype(M::constraint_directions(
                                    std::declval<const typename M::State&>(), std::declval<typename M::ConstraintSystem&>()))>>
    : std::true_type {};
template <class M, class = void>
struct accelerations_read_state : std::false_type {};
template <class M>
struct accelerations_read_state<M, std::void_t<decltype(M::free_accelerations(std::declval<const typename M::State&>(),
                                                                               std::declval<const typename M::Loads&>()))>>
    : std::true_type {};
template <class M, class = void>
struct factorize_reads_state : std::false_type {};
template <class M>
struct factorize_reads_state<M, std::void_t<decltype(M::factorize(std::declval<const typename M::State&>(),
                                                                  std::declval<typename M::ConstraintSystem&>()))>>
    : std::true_type {};

template <class M, class = void>
struct tree_factorize_reads_state : std::false_type {};
template <class M>
struct tree_factorize_reads_state<M, std::void_t<decltype(M::factorize_tree(
                                         std::declval<const typename M::State&>(), std::declval<const typename M::Kinematics&>(),
                                         std::declval<const typename M::ConstraintSystem&>(),
                                         std::declval<typename M::TreeSystem&>()))>> : std::true_type {};

template <class M>
void constraint_directions(const typename M::State& s, typename M::ConstraintSystem& c) noexcept {
  if constexpr (directions_read_state<M>::value) M::constraint_directions(s, c);
  else M::constraint_directions(c);
}

template <class M>
typename M::BodyVectors free_accelerations(const typename M::State& s, const typename M::Loads& l) noexcept {
  if constexpr (accelerations_read_state<M>::value) return M::free_accelerations(s, l);
  else return M::free_accelerations(l);
}

template <class M>
bool factorize_system(const typename M::State& s, typename M::ConstraintSystem& c) noexcept {
  if constexpr (factorize_reads_state<M>::value) return M::factorize(s, c);
  else return M::factorize(c);
}

// (c, l, u_half) => (u): staggered-pcst's implicit stage. The end-of-step
// velocities satisfy the velocity constraints, regularized by the penalty eps
// (docs/staggered-pcst.md eq. 5):
//   (h/2) (S + 2 eps/h I) mu = B u_hat,  u = u_hat - h/2 M^-1 B^T mu.
template <class M>
void implicit_stage(const typename M::State& s, const typename M::ConstraintSystem& c, const typename M::Loads& l,
                    const typename M::BodyVectors& u_half, typename M::BodyVectors& u) noexcept {
  constexpr double h = M::kStep;
  const typename M::BodyVectors a_free = free_accelerations<M>(s, l);
  for (std::size_t b = 0; b < u.size(); ++b) u[b] = u_half[b] + (0.5 * h) * a_free[b];
  typename M::Rows mu = (2.0 / h) * M::velocity_residual(c, u);
  M::solve(c, mu);
  M::subtract_constraint_forces(c, mu, 0.5 * h, u);
}

// (w.c0, w.c, u_kick, w.last_good) => (s, w.k, w.c rows): the position stage.
// The first half kick's constraint forces act along M^-1 B(q(t))^T; their
// multipliers are corrected so that the drift lands on Phi(q(t + h)) = 0
// (RATTLE's position step: Andersen 1983, "Rattle: a velocity version of the
// Shake algorithm", J. Comput. Phys. 52, eqs. 2.6-2.9), by Newton steps with
// the matrix G = B(q*) M^-1 B(q(t))^T of the first drift q*. Correcting along
// B(q(t))^T rather than B(q(t + h))^T is what keeps the energy of
// fast-turning bodies bounded (docs/stability.md).
template <class M>
void position_stage(typename M::BodyVectors& u_kick, typename M::State& s, typename M::Workspace& w) noexcept {
  M::factorize_newton(w.c0, w.c, w.g);
  for (int i = 0; i < M::kPositionIterations; ++i) {
    typename M::Rows x = M::stacked_phi(w.c);
    typename M::Rows y = x;
    M::solve_newton(w.g, x);
    // G is close to singular where a long chain turns by more than its softest
    // modes allow; a Newton step larger than S(q*)'s is then not trusted.
    M::solve(w.c, y);
    if (!(x.squaredNorm() <= 4.0 * y.squaredNorm())) x = y;
    M::subtract_constraint_forces(w.c0, x, 1.0 / M::kStep, u_kick);
    set_positions(w.last_good, s);
    M::set_velocities(u_kick, s);
    M::drift(s);
    M::kinematics(s, w.k);
    if (i + 1 < M::kPositionIterations) M::constraint_rows(w.k, s, w.c);
  }
}

// (c, s) => (s): blajer's mass-orthogonal velocity correction (Blajer 1997,
// "A projection method approach to constrained dynamic analysis", eq. 40),
// du = -M^-1 B^T S^-1 B u.
template <class M>
void correct_velocities(const typename M::ConstraintSystem& c, typename M::State& s) noexcept {
  typename M::BodyVectors u = M::generalized_velocities(s);
  typename M::Rows x = M::velocity_residual(c, u);
  M::solve(c, x);
  M::subtract_constraint_forces(c, x, 1.0, u);
  M::set_velocities(u, s);
}

// The impulse step where a contact's body is in a joint (docs/contact.md)
// or a joint has friction (docs/friction.md): S factorized at the step's
// end gives the joints' share of each impulse. The impulses' displacement
// (h/2 of the velocity change) is tangent to the joints, off them at second
// order (a rebounding rod turned about its pin by h/2 dw moves its centre
// along the tangent): one mass-orthogonal Newton step puts the positions
// back on the joints (then joints stuck by friction are held where they
// started) and the velocities are projected onto them (Blajer 1997, eqs. 38
// and 40), else the next step's stabilization would pay for the gap in
// energy. Then the accelerations and multipliers at the velocities the
// impulses left, which the next step starts from (the rod's centripetal
// load after it rebounds), with the joints' share of the contact and
// friction forces added to the multipliers. Returns whether S was positive
// definite.
template <class M>
bool impulse_step_with_joints(typename M::State& s, typename M::Workspace& w) noexcept {
  using BodyVectors = typename M::BodyVectors;
  // rk4-projected and baumgarte end their smooth step with S factorized at
  // its final positions (only velocities change after); staggered-pcst's
  // position stage and blajer's corrections move them after their factorization.
  constexpr bool factor_current = M::kScheme == Scheme::rk4_projected || M::kScheme == Scheme::baumgarte;
  bool positive = true;
  if constexpr (!factor_current) {
    M::kinematics(s, w.k);
    M::constraint_rows(w.k, s, w.c);
    positive = factorize_system<M>(s, w.c);
  }
  [[maybe_unused]] std::conditional_t<(kFrictionJointsOf<M> > 0), FrictionHold<M>, int> hold{};
  typename M::Rows joint_forces;
  if constexpr (kFrictionJointsOf<M> > 0) {
    // Friction acts on the joints' rates: first B u = 0 to round-off, which
    // staggered-pcst's penalty, baumgarte's and blajer's steps only approach
    // (a stuck joint would keep their residual); rk4-projected has projected.
    if constexpr (M::kScheme != Scheme::rk4_projected) correct_velocities<M>(w.c, s);
    if constexpr (has_contacts<M>::value) joint_forces = contacts_and_joint_friction<M>(s, w, Joints<M>{&w.c}, hold);
    else joint_forces = absolute_joint_friction<M>(s, w, Joints<M>{&w.c}, hold);
  } else {
    joint_forces = contact_step<M>(w.last_good, s, &w.c);
  }
  M::kinematics(s, w.k);
  M::constraint_rows(w.k, s, w.c);
  positive = factorize_system<M>(s, w.c) && positive;
  typename M::Rows z = M::stacked_phi(w.c);
  M::solve(w.c, z);
  BodyVectors dq;
  for (auto& d : dq) d.setZero();
  M::subtract_constraint_forces(w.c, z, 1.0, dq);
  M::displace(dq, s);
  if constexpr (kFrictionJointsOf<M> > 0) hold_stuck_joints<M>(s, w, hold);
  correct_velocities<M>(w.c, s);
  // The rows at the corrected positions (the factor and directions stay,
  // off by the correction), the velocity terms at the new velocities.
  M::kinematics(s, w.k);
  w.k.vel = M::velocities_of(s);
  M::constraint_rows(w.k, s, w.c);
  M::applied_loads(w.k, s, w.l);
  M::constraint_forces(w.c, w.l, M::stacked_phi(w.c), s);
  s.lambda += joint_forces;
  return positive;
}

// The contacts and joint friction after a scheme's smooth step: with the
// joints' share where an impulse acts on a body in a joint. Returns whether
// S was positive definite.
template <class M>
bool contacts_after_smooth_step(typename M::State& s, typename M::Workspace& w) noexcept {
  if constexpr (jointed_contacts<M>() || kFrictionJointsOf<M> > 0) {
    return impulse_step_with_joints<M>(s, w);
  } else {
    contact_step<M>(w.last_good, s);
    return true;
  }
}

// staggered-nps factorizes the tree and the cut rows where the others factorize S;
// its tree elimination takes the state where masses are runtime parameters.
template <class M>
bool factorize(const typename M::State& s, typename M::Workspace& w) noexcept {
  if constexpr (M::kScheme == Scheme::staggered_nps) {
    bool positive;
    if constexpr (tree_factorize_reads_state<M>::value) positive = M::factorize_tree(s, w.k, w.c, w.t);
    else positive = M::factorize_tree(w.k, w.c, w.t);
    if constexpr (M::kCutRows > 0) positive = M::factorize_cut(w.c, w.t) && positive;
    return positive;
  } else {
    return factorize_system<M>(s, w.c);
  }
}

// (s, accelerations at t) => (s at t + h, its accelerations and multipliers).
// Allocates nothing, throws nothing, fixed work; on a non-finite result or a
// lost factorization s keeps its old value.
template <class M>
StepStatus staggered_step(typename M::State& s, typename M::Workspace& w) noexcept {
  using BodyVectors = typename M::BodyVectors;
  constexpr double h = M::kStep;
  constexpr bool index1 = M::kScheme == Scheme::baumgarte || M::kScheme == Scheme::blajer;
  w.last_good = s;
  const BodyVectors a_old = M::accelerations_of(s);
  bool positive = true;
  if constexpr (M::kPositionStage) {
    // Directions of the first half kick's constraint forces, at q(t).
    M::kinematics(s, w.k);
    M::constraint_rows(w.k, s, w.c0);
    constraint_directions<M>(s, w.c0);
    M::kick(s);
    BodyVectors u_kick = M::generalized_velocities(s);
    M::drift(s);
    // Constraint terms at the drifted positions, factorized once per step; the
    // position stage moves the positions onto the constraints and keeps the factor.
    M::kinematics(s, w.k);
    M::constraint_rows(w.k, s, w.c);
    positive = factorize_system<M>(s, w.c);
    position_stage<M>(u_kick, s, w);
  } else {
    M::kick(s);
    M::drift(s);
  }
  const BodyVectors u_half = M::generalized_velocities(s);
  if constexpr (!M::kPositionStage) M::kinematics(s, w.k);

  if constexpr (!index1) {
    // Constraint terms at the new positions. The quadratic terms are taken at
    // the predicted next half-step velocity u_half + h a_old, which the next
    // explicit stage will drift with.
    BodyVectors u = u_half;
    for (std::size_t b = 0; b < u.size(); ++b) u[b] += h * a_old[b];
    M::set_velocities(u, s);
    w.k.vel = M::velocities_of(s);
    M::constraint_rows(w.k, s, w.c);
    if constexpr (M::kScheme == Scheme::staggered4) {
      // RATTLE's velocity projection, B(q(t + h)) u = 0 to round-off, which
      // the factor of the first drift's S only approximates; the symmetry
      // that keeps staggered4's energy from drifting needs it (docs/schemes.md).
      positive = factorize<M>(s, w) && positive;
    } else if constexpr (M::kPositionStage) {
      constraint_directions<M>(s, w.c);  // the factor stays that of the first drift
    } else {
      positive = factorize<M>(s, w);
    }
    // Implicit stages: the first evaluates velocity-dependent loads at the
    // predicted end-of-step velocities u_half + h/2 a_old, the next ones at
    // the last result.
    for (std::size_t b = 0; b < u.size(); ++b) u[b] = u_half[b] + (0.5 * h) * a_old[b];
    for (int stage = 0; stage < M::kStages; ++stage) {
      M::set_velocities(u, s);
      w.k.vel = M::velocities_of(s);
      M::applied_loads(w.k, s, w.l);
      if constexpr (M::kScheme == Scheme::staggered_nps) {
        M::implicit_stage(w.c, w.t, w.l, u_half, u);
      } else {
        implicit_stage<M>(s, w.c, w.l, u_half, u);
      }
    }
    M::set_velocities(u, s);
    // The projection twice more, which removes the residual S's
    // regularization leaves (1e-10 of B u; more along redundant rows).
    if constexpr (M::kScheme == Scheme::staggered4) {
      correct_velocities<M>(w.c, s);
      correct_velocities<M>(w.c, s);
    }
    if constexpr (M::kScheme == Scheme::staggered_nps) {
      M::constraint_forces(w.c, w.t, w.l, M::stacked_phi(w.c), s);
    } else {
      M::constraint_forces(w.c, w.l, M::stacked_phi(w.c), s);
    }
  } else {
    // Constraint terms at the new positions, factorized once per step, with
    // the quadratic terms at the predicted end-of-step velocity.
    BodyVectors u = u_half;
    for (std::size_t b = 0; b < u.size(); ++b) u[b] += (0.5 * h) * a_old[b];
    M::set_velocities(u, s);
    w.k.vel = M::velocities_of(s);
    M::constraint_rows(w.k, s, w.c);
    positive = factorize_system<M>(s, w.c);
    const typename M::Rows phi = M::stacked_phi(w.c);
    // Implicit stages, fixed-point passes on u = u_half + h/2 a(t + h, u).
    for (int stage = 0; stage < M::kStages; ++stage) {
      M::set_velocities(u, s);
      w.k.vel = M::velocities_of(s);
      M::applied_loads(w.k, s, w.l);
      M::constraint_forces(w.c, w.l, phi, s);
      const BodyVectors a = M::accelerations_of(s);
      for (std::size_t b = 0; b < u.size(); ++b) u[b] = u_half[b] + (0.5 * h) * a[b];
    }
    M::set_velocities(u, s);
    if constexpr (M::kScheme == Scheme::blajer) {
      // Post-step corrections, a fixed number for positions, then velocities.
      for (int i = 0; i < M::kCorrections; ++i) {
        if (i > 0) {
          M::kinematics(s, w.k);
          M::constraint_rows(w.k, s, w.c);
          positive = factorize_system<M>(s, w.c) && positive;
        }
        M::correct_positions(w.c, s);
      }
      correct_velocities<M>(w.c, s);
    }
  }

  // Unilateral contacts and their friction (docs/contact.md), joint friction
  // (docs/friction.md).
  positive = contacts_after_smooth_step<M>(s, w) && positive;
  if (!finite(s)) {
    s = w.last_good;
    return StepStatus::non_finite;
  }
  if (!positive) {
    s = w.last_good;
    return StepStatus::not_positive;
  }
  return StepStatus::ok;
}

}  // namespace mbrt::schemes
