// The step of ali3p: index-3 augmented Lagrangian with the trapezoidal rule
// or generalized-alpha, then velocity and acceleration projections (Dopico,
// Gonzalez, Cuadrado & Kovecses 2014, "Determination of holonomic and
// nonholonomic constraint reactions in an index-3 augmented Lagrangian
// formulation with velocity and acceleration projections", J. Comput.
// Nonlinear Dynam. 9; docs/ali3p.md).
//
// M is a generated model (struct Model in the model's source). It provides
//   types     State, Workspace, Rows, BodyVectors;
//   constants kStep, kNewtonIterations, kWeighted (generalized-alpha keeps
//             M^-1 (B^T lambda - F) of the last step), kRheonomic, kAlpha,
//             kTangentShift, kProjectionShift;
//   kernels   kinematics, velocities_of, generalized_velocities, set_velocities,
//             accelerations_of, set_accelerations, applied_loads, constraint_rows,
//             factorize(c, shift), stacked_phi, stacked_phi_t, stacked_quad,
//             newmark_update, newton_correction, constraint_minus_applied, project;
//             the kernels that form M^-1 with the state first where masses are
//             runtime parameters (below).
// Workspace holds last_good (the state at t), k, c and l.
#pragma once

#include <type_traits>
#include <utility>

#include "mbrt/contacts.hpp"
#include "mbrt/scheme.hpp"
#include "mbrt/schemes/staggered.hpp"
#include "mbrt/schemes/state_checks.hpp"
#include "mbrt/step_status.hpp"

namespace mbrt::schemes {

// The kernels that form M^-1 (factorize, newton_correction,
// constraint_minus_applied, free_accelerations) take the state where masses
// are runtime parameters (docs/parameters.md); told apart by factorize's form.
template <class M, class = void>
struct ali3p_reads_state : std::false_type {};
template <class M>
struct ali3p_reads_state<M, std::void_t<decltype(M::factorize(std::declval<const typename M::State&>(),
                                                              std::declval<typename M::ConstraintSystem&>(),
                                                              std::declval<const typename M::Rows&>()))>>
    : std::true_type {};

template <class M>
bool ali3p_factorize(const typename M::State& s, typename M::ConstraintSystem& c, const typename M::Rows& shift) noexcept {
  if constexpr (ali3p_reads_state<M>::value) return M::factorize(s, c, shift);
  else return M::factorize(c, shift);
}

template <class M>
typename M::BodyVectors ali3p_constraint_minus_applied(const typename M::State& s, const typename M::ConstraintSystem& c,
                                                       const typename M::Loads& l, const typename M::Rows& lambda) noexcept {
  if constexpr (ali3p_reads_state<M>::value) return M::constraint_minus_applied(s, c, l, lambda);
  else return M::constraint_minus_applied(c, l, lambda);
}

// newton_correction(c, l, lambda, [a_n, g_n,] a), with the state first where it reads it.
template <class M, class... Args>
void ali3p_newton_correction(const typename M::State& s, Args&&... args) noexcept {
  if constexpr (ali3p_reads_state<M>::value) M::newton_correction(s, std::forward<Args>(args)...);
  else M::newton_correction(std::forward<Args>(args)...);
}

// (a, s, w.c factorized with kProjectionShift) => (lambda): the multipliers
// whose forces give the accelerations a by Newton's law at the step's end,
// B^T lambda = F - M a, in M^-1's metric: S lambda = B (M^-1 F - a).
// lambda* + alpha Phi + nu (Q = Q_dyn + Q_acc, Dopico et al. 2014, eq. 51)
// sums to the same up to round-off times alpha: Phi is known to about 1e-16
// of the bodies' distance from the origin, and alpha reaches 1e13 and more,
// which put 1e-2 of m g of noise on a pendulum's rod force. One refinement
// removes the shift's share: (S + d) x = b, then x += (S + d)^-1 d x.
template <class M>
typename M::Rows newton_multipliers(const typename M::BodyVectors& a, typename M::State& s,
                                    typename M::Workspace& w) noexcept {
  using Rows = typename M::Rows;
  M::applied_loads(w.k, s, w.l);
  typename M::BodyVectors residual = free_accelerations<M>(s, w.l);
  for (std::size_t b = 0; b < residual.size(); ++b) residual[b] -= a[b];
  Rows lambda = M::jacobian_times(w.c, residual);
  M::solve(w.c, lambda);
  Rows correction = M::kProjectionShift.cwiseProduct(lambda);
  M::solve(w.c, correction);
  return lambda + correction;
}

template <class M>
StepStatus ali3p_step(typename M::State& s, typename M::Workspace& w) noexcept {
  using BodyVectors = typename M::BodyVectors;
  using Rows = typename M::Rows;
  const typename M::State& n = w.last_good;
  w.last_good = s;
  const BodyVectors u_n = M::generalized_velocities(n);
  const BodyVectors a_n = M::accelerations_of(n);
  s.t += M::kStep;

  // Newton iterations on the accelerations from the predictor a = a_n
  // (q = q_n + h u_n + h^2/2 a_n), the multipliers lambda* updated by
  // alpha phi from the second iteration on (Dopico et al. 2014, sec. 3.3).
  BodyVectors a = a_n;
  BodyVectors u;
  Rows lambda_star = n.ali3p_lambda_star;
  bool positive = true;
  for (int i = 0; i < M::kNewtonIterations; ++i) {
    M::newmark_update(n, u_n, a_n, a, s, u);
    M::kinematics(s, w.k);
    M::constraint_rows(w.k, s, w.c);
    const Rows phi = M::stacked_phi(w.c);
    if (i > 0) lambda_star += M::kAlpha.cwiseProduct(phi);
    M::applied_loads(w.k, s, w.l);
    positive = ali3p_factorize<M>(s, w.c, M::kTangentShift) && positive;
    if constexpr (M::kWeighted) {
      ali3p_newton_correction<M>(s, w.c, w.l, lambda_star + M::kAlpha.cwiseProduct(phi), a_n, n.ali3p_force, a);
    } else {
      ali3p_newton_correction<M>(s, w.c, w.l, lambda_star + M::kAlpha.cwiseProduct(phi), a);
    }
  }

  // The step's positions; the multipliers lambda* + alpha phi (eq. 36) are
  // the dynamic part of the constraint forces and the next step's start.
  M::newmark_update(n, u_n, a_n, a, s, u);
  M::kinematics(s, w.k);
  M::constraint_rows(w.k, s, w.c);
  s.lambda = lambda_star + M::kAlpha.cwiseProduct(M::stacked_phi(w.c));
  s.ali3p_lambda_star = s.lambda;
  if constexpr (M::kWeighted) {
    M::applied_loads(w.k, s, w.l);
    s.ali3p_force = ali3p_constraint_minus_applied<M>(s, w.c, w.l, s.lambda);
  }

  // Velocity projection, then the acceleration projection with the
  // acceleration terms at the projected velocities.
  positive = ali3p_factorize<M>(s, w.c, M::kProjectionShift) && positive;
  if constexpr (M::kRheonomic) {
    M::project(w.c, M::stacked_phi_t(w.c), u);
  } else {
    M::project(w.c, Rows::Zero(), u);
  }
  M::set_velocities(u, s);
  w.k.vel = M::velocities_of(s);
  M::constraint_rows(w.k, s, w.c);
  M::project(w.c, M::stacked_quad(w.c), a);
  M::set_accelerations(a, s);
  s.lambda = newton_multipliers<M>(a, s, w);

  contact_step<M>(w.last_good, s);  // unilateral contacts and their friction, docs/contact.md
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
