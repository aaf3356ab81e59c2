// The step of rk4-projected (docs/schemes.md, "rk4-projected"): the classical
// Runge-Kutta method of order four (Hairer, Norsett & Wanner 1993, "Solving
// Ordinary Differential Equations I", table II.1.2) on the absolute
// coordinates, y = (r, p, v, w) per body, y' = (v, 1/2 p * (0, w), a, alpha),
// with each stage's accelerations from the index-1 multipliers
// S lambda = B M^-1 F + quad (Blajer 1997, "A projection method approach to
// constrained dynamic analysis", eq. 26). After the step the Euler parameters
// are normalized, the positions corrected mass-orthogonally onto Phi = 0
// (eq. 38, kCorrections times) and the velocities onto the velocity
// constraints (eq. 40): a projection method, which keeps the order of the
// method it projects (Hairer, Lubich & Wanner 2006, "Geometric Numerical
// Integration", section IV.4).
//
// M is a generated model (struct Model in the model's source, spatial
// coordinates). It provides blajer's kernels (include/mbrt/schemes/staggered.hpp;
// factorize takes the state where masses are runtime parameters)
// and the constants kStep, kCorrections and kInputs (the model has inputs,
// which may change between steps).
// Workspace holds last_good (the state at t), k, c, l, sum (the stages'
// weighted rates, in a State's fields) and p_stage (each rigid body's Euler
// parameters in the stage, before normalizing).
#pragma once

#include "mbrt/rotation.hpp"
#include "mbrt/schemes/staggered.hpp"

namespace mbrt::schemes {

// (s) => (s's accelerations and multipliers, w.k, w.c factorized at s).
template <class M>
bool rk4_projected_evaluate(typename M::State& s, typename M::Workspace& w) noexcept {
  M::kinematics(s, w.k);
  M::constraint_rows(w.k, s, w.c);
  const bool positive = factorize_system<M>(s, w.c);
  M::applied_loads(w.k, s, w.l);
  M::constraint_forces(w.c, w.l, M::stacked_phi(w.c), s);
  return positive;
}

// (s, w.p_stage: a stage with its accelerations) => (w.sum += weight * y'(stage)).
template <class M>
void rk4_projected_accumulate(const typename M::State& s, double weight, bool first, typename M::Workspace& w) noexcept {
  const auto add = [first, weight](auto& sum, const auto& rate) {
    if (first) sum = weight * rate;
    else sum += weight * rate;
  };
  for (std::size_t b = 0; b < s.rigid.size(); ++b) {
    add(w.sum.rigid[b].r, s.rigid[b].v);
    add(w.sum.rigid[b].p, euler_parameter_rate(w.p_stage[b], s.rigid[b].w));
    add(w.sum.rigid[b].v, s.rigid_acceleration[b].a);
    add(w.sum.rigid[b].w, s.rigid_acceleration[b].alpha);
  }
  for (std::size_t b = 0; b < s.particle.size(); ++b) {
    add(w.sum.particle[b].r, s.particle[b].v);
    add(w.sum.particle[b].v, s.particle_acceleration[b]);
  }
}

// (s at a stage, y0) => (s at the next stage, y0 + dt y'(stage)); the Euler
// parameters the kinematics sees are the stage's normalized.
template <class M>
void rk4_projected_advance(const typename M::State& y0, double dt, typename M::State& s,
                           typename M::Workspace& w) noexcept {
  for (std::size_t b = 0; b < s.rigid.size(); ++b) {
    RigidState& x = s.rigid[b];
    const RigidState& x0 = y0.rigid[b];
    w.p_stage[b] = x0.p + dt * euler_parameter_rate(w.p_stage[b], x.w);
    x.p = w.p_stage[b].normalized();
    x.r = x0.r + dt * x.v;
    x.v = x0.v + dt * s.rigid_acceleration[b].a;
    x.w = x0.w + dt * s.rigid_acceleration[b].alpha;
  }
  for (std::size_t b = 0; b < s.particle.size(); ++b) {
    s.particle[b].r = y0.particle[b].r + dt * s.particle[b].v;
    s.particle[b].v = y0.particle[b].v + dt * s.particle_acceleration[b];
  }
  s.t = y0.t + dt;
}

// (s with its accelerations) => (s at t + h with its accelerations and
// multipliers). Four evaluations of the accelerations, the first carried in
// s from the last step (fresh where inputs may have changed since), the last
// at the projected end-of-step state. Allocates nothing, throws nothing,
// fixed work; on a non-finite result or a lost factorization s keeps its
// old value.
template <class M>
StepStatus rk4_projected_step(typename M::State& s, typename M::Workspace& w) noexcept {
  constexpr double h = M::kStep;
  constexpr double kAdvance[4] = {0.0, 0.5 * h, 0.5 * h, h};  // each stage's point from the last stage's slope
  constexpr double kWeight[4] = {h / 6.0, h / 3.0, h / 3.0, h / 6.0};
  w.last_good = s;
  const typename M::State& y0 = w.last_good;
  bool positive = true;
  if constexpr (M::kInputs) positive = rk4_projected_evaluate<M>(s, w);
  for (std::size_t b = 0; b < s.rigid.size(); ++b) w.p_stage[b] = y0.rigid[b].p;
  for (int stage = 0; stage < 4; ++stage) {
    if (stage > 0) {
      rk4_projected_advance<M>(y0, kAdvance[stage], s, w);
      positive = rk4_projected_evaluate<M>(s, w) && positive;
    }
    rk4_projected_accumulate<M>(s, kWeight[stage], stage == 0, w);
  }
  for (std::size_t b = 0; b < s.rigid.size(); ++b) {
    RigidState& x = s.rigid[b];
    x.r = y0.rigid[b].r + w.sum.rigid[b].r;
    x.p = (y0.rigid[b].p + w.sum.rigid[b].p).normalized();
    x.v = y0.rigid[b].v + w.sum.rigid[b].v;
    x.w = y0.rigid[b].w + w.sum.rigid[b].w;
  }
  for (std::size_t b = 0; b < s.particle.size(); ++b) {
    s.particle[b].r = y0.particle[b].r + w.sum.particle[b].r;
    s.particle[b].v = y0.particle[b].v + w.sum.particle[b].v;
  }
  s.t = y0.t + h;

  // Projections: positions kCorrections times, then velocities, each with S
  // factorized where it is applied; then the accelerations at the result.
  for (int i = 0; i < M::kCorrections; ++i) {
    M::kinematics(s, w.k);
    M::constraint_rows(w.k, s, w.c);
    positive = factorize_system<M>(s, w.c) && positive;
    M::correct_positions(w.c, s);
  }
  M::kinematics(s, w.k);
  M::constraint_rows(w.k, s, w.c);
  positive = factorize_system<M>(s, w.c) && positive;
  correct_velocities<M>(w.c, s);
  w.k.vel = M::velocities_of(s);
  M::constraint_rows(w.k, s, w.c);  // the acceleration terms at the projected velocities
  M::applied_loads(w.k, s, w.l);
  M::constraint_forces(w.c, w.l, M::stacked_phi(w.c), s);

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
