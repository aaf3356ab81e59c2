// The staggered-tree step (docs/staggered-tree.md): the staggered
// explicit-implicit integrator of Park & Chiou 1988 ("Stabilization of
// computational procedures for constrained dynamical systems", J. Guidance
// 11(4)) on the joint coordinates of a tree, natural partitioning in the
// sense of Chiou 1990: the joints' rates are the independent velocities and
// the bodies' velocities follow body by body, so the joints hold exactly and
// need no multipliers. The accelerations come from the articulated-body
// recursion (Featherstone 2008, "Rigid Body Dynamics Algorithms", table 7.1)
// that the generator writes out for the model.
//
// tree_midpoint_step (midpoint-tree) takes the same model through the
// implicit midpoint rule instead, for energy at 1 kHz on trees of many links,
// and tree_rk4_step (rk4-tree) and tree_rk8_step (rk8-tree) through explicit
// Runge-Kutta methods of order four and eight, for high precision at large
// steps.
//
// M is a generated model (struct Model in the model's source). It provides
//   types     State (t, q, qd, qdd, rigid, ...), Workspace (with
//             stage_rates and stage_accelerations, kStages Dofs each, for
//             the Runge-Kutta steps), Dofs, HalfAngles;
//   constants kStep, kStages (recursions per step), kExternalLoads,
//             kBodyStatesEachStep;
//   kernels   half_angles, body_states, kinematics, tree_loads,
//             joint_accelerations;
// and, where joints have friction, what joint_friction.hpp needs: each step
// applies the friction impulses to the rates it ends with (tree_friction).
#pragma once

#include <cmath>
#include <cstddef>
#include <utility>

#include "mbrt/mul_add.hpp"
#include "mbrt/scheme.hpp"
#include "mbrt/body_state.hpp"
#include "mbrt/schemes/joint_friction.hpp"
#include "mbrt/schemes/runge_kutta_tableaus.hpp"
#include "mbrt/step_status.hpp"

namespace mbrt::schemes {

// The joint coordinates decide everything else (the rates after the last
// kick carry the accelerations); a body's velocity is where finite rates
// could still overflow. Where the step does not form the bodies' states
// (M::kBodyStatesEachStep false), the accelerations stand in for them.
template <class M>
bool tree_state_finite(const typename M::State& s) noexcept {
  double sum = 0.0;
  for (std::size_t i = 0; i < s.q.size(); ++i) sum += s.q[i] + s.qd[i];
  if constexpr (M::kBodyStatesEachStep) {
    for (const RigidState& b : s.rigid) sum += b.v.sum();
  } else {
    for (const double a : s.qdd) sum += a;
  }
  return std::isfinite(sum);
}

// The bodies' states at the step's end, s.rigid, unless the model forms
// them only on request (solver.body_states: on_demand, refresh_bodies());
// then s.rigid after a step is not the new state's (where loads need them,
// a stage's).
template <class M>
void tree_body_states(typename M::State& s, typename M::Workspace& w) noexcept {
  if constexpr (M::kBodyStatesEachStep) M::body_states(s.q, w.half_angles, s.qd, s);
}

// The end of a step whose last recursion ran at other joint coordinates:
// the half angles of the final q, which only the friction impulses and the
// bodies' states turn frames by, then those two.
template <class M>
void tree_step_close(typename M::State& s, typename M::Workspace& w) noexcept {
  if constexpr (M::kBodyStatesEachStep || kFrictionJointsOf<M> > 0) M::half_angles(s.q, w.half_angles);
  tree_friction<M>(s, w);
  tree_body_states<M>(s, w);
}

// A step's first act: save what tree_step_end restores.
template <class M>
void tree_step_begin(const typename M::State& s, typename M::Workspace& w) noexcept {
  w.t0 = s.t;
  w.q0 = s.q;
  w.qd0 = s.qd;
  w.qdd0 = s.qdd;
}

// A step's last act: keep the new state if it is finite, else restore the
// one the step began from (saved in w by tree_step_begin).
template <class M>
StepStatus tree_step_end(typename M::State& s, typename M::Workspace& w) noexcept {
  if (tree_state_finite<M>(s)) return StepStatus::ok;
  s.t = w.t0;
  s.q = w.q0;
  s.qd = w.qd0;
  s.qdd = w.qdd0;
  // The bodies too, even on demand: a stage may have left non-finite ones.
  M::half_angles(s.q, w.half_angles);
  M::body_states(s.q, w.half_angles, s.qd, s);
  return StepStatus::non_finite;
}

// The accelerations at joint coordinates s.q and rates w.rates at time s.t
// (and parameters s.params, where the model has runtime parameters)
// into s.qdd: one recursion, and the bodies' states first where loads other
// than gravity need them.
template <class M>
void tree_accelerations(typename M::State& s, typename M::Workspace& w) noexcept {
  M::half_angles(s.q, w.half_angles);
  if constexpr (M::kExternalLoads) {
    M::body_states(s.q, w.half_angles, w.rates, s);
    M::kinematics(s, w.k);
    M::tree_loads(w.k, s, w.l);
  }
  M::joint_accelerations(s, w.half_angles, w.rates, w.k, w.l, s.qdd);
}

// (s with accelerations at t) => (s at t + h). Allocates nothing, throws
// nothing, fixed work; on a non-finite result s keeps its old value.
template <class M>
StepStatus tree_step(typename M::State& s, typename M::Workspace& w) noexcept {
  constexpr double h = M::kStep;
  tree_step_begin<M>(s, w);
  // Explicit stage: half kick and drift of the joint coordinates.
  for (std::size_t i = 0; i < s.q.size(); ++i) {
    s.qd[i] += (0.5 * h) * s.qdd[i];
    s.q[i] += h * s.qd[i];
  }
  s.t += h;
  M::half_angles(s.q, w.half_angles);
  // Implicit stage: accelerations at the new positions and the end-of-step
  // rates, predicted from the last accelerations (a second pass uses the new ones).
  for (int stage = 0; stage < M::kStages; ++stage) {
    for (std::size_t i = 0; i < s.q.size(); ++i) w.rates[i] = s.qd[i] + (0.5 * h) * s.qdd[i];
    if constexpr (M::kExternalLoads) {
      M::body_states(s.q, w.half_angles, w.rates, s);
      M::kinematics(s, w.k);
      M::tree_loads(w.k, s, w.l);
    }
    M::joint_accelerations(s, w.half_angles, w.rates, w.k, w.l, s.qdd);
  }
  for (std::size_t i = 0; i < s.q.size(); ++i) s.qd[i] += (0.5 * h) * s.qdd[i];
  tree_friction<M>(s, w);
  tree_body_states<M>(s, w);
  return tree_step_end<M>(s, w);
}

// The implicit midpoint rule on the joint coordinates and their rates
// (Hairer, Lubich & Wanner 2006, "Geometric Numerical Integration", eq.
// I.1.7): with the midpoint qm = q + h/2 vm, vm = qd + h/2 a and
// a = qdd(qm, vm),
//   q(t + h) = q + h vm,   qd(t + h) = qd + h a,
// so the step of q is the mean of the two rates. It is symmetric, so on
// these reversible systems the energy oscillates instead of drifting, where
// kick-drift-kick in joint coordinates (tree_step) lets it wander once the
// mass matrix depends on q. kStages fixed-point iterations, each one
// recursion at the midpoint, start from the last step's midpoint
// accelerations, which s.qdd carries; nothing else carries over.
// (s with the last midpoint's accelerations) => (s at t + h). Allocates
// nothing, throws nothing, fixed work; on a non-finite result s keeps its
// old value.
template <class M>
StepStatus tree_midpoint_step(typename M::State& s, typename M::Workspace& w) noexcept {
  constexpr double h = M::kStep;
  tree_step_begin<M>(s, w);
  s.t = w.t0 + 0.5 * h;
  for (int iteration = 0; iteration < M::kStages; ++iteration) {
    for (std::size_t i = 0; i < s.q.size(); ++i) {
      w.rates[i] = w.qd0[i] + (0.5 * h) * s.qdd[i];
      s.q[i] = w.q0[i] + (0.5 * h) * w.rates[i];
    }
    tree_accelerations<M>(s, w);
  }
  for (std::size_t i = 0; i < s.q.size(); ++i) {
    s.q[i] = w.q0[i] + h * (w.qd0[i] + (0.5 * h) * s.qdd[i]);
    s.qd[i] = w.qd0[i] + h * s.qdd[i];
  }
  s.t = w.t0 + h;
  tree_step_close<M>(s, w);
  return tree_step_end<M>(s, w);
}

namespace tree_detail {

// sum += h coefficient k[i], left out where the coefficient is zero.
template <class M, double kCoefficient, class Slope>
void add_slope(double& sum, const Slope& k, std::size_t i) noexcept {
  if constexpr (kCoefficient != 0.0) sum = mul_add(M::kStep * kCoefficient, k[i], sum);
}

// start + sum_{j<Row} h a_{Row j} k_j[i].
template <class M, class Tableau, int Row, class Slopes, std::size_t... J>
double stage_point(double start, [[maybe_unused]] const Slopes& k, [[maybe_unused]] std::size_t i,
                   std::index_sequence<J...>) noexcept {
  (add_slope<M, Tableau::a[Row][J]>(start, k[J], i), ...);
  return start;
}

// start + sum_j h b_j k_j[i].
template <class M, class Tableau, class Slopes, std::size_t... J>
double step_end(double start, const Slopes& k, std::size_t i, std::index_sequence<J...>) noexcept {
  (add_slope<M, Tableau::b[J]>(start, k[J], i), ...);
  return start;
}

// Stage Row: the joint coordinates and rates at its point, one recursion
// there, its slopes kept in w.stage_rates[Row] and w.stage_accelerations[Row].
template <class M, class Tableau, int Row>
void runge_kutta_stage(typename M::State& s, typename M::Workspace& w) noexcept {
  constexpr auto earlier = std::make_index_sequence<Row>{};
  for (std::size_t i = 0; i < s.q.size(); ++i) {
    s.q[i] = stage_point<M, Tableau, Row>(w.q0[i], w.stage_rates, i, earlier);
    w.rates[i] = stage_point<M, Tableau, Row>(w.qd0[i], w.stage_accelerations, i, earlier);
  }
  s.t = w.t0 + Tableau::c[Row] * M::kStep;
  tree_accelerations<M>(s, w);
  w.stage_rates[Row] = w.rates;
  w.stage_accelerations[Row] = s.qdd;
}

template <class M, class Tableau, std::size_t... Row>
void runge_kutta_stages(typename M::State& s, typename M::Workspace& w, std::index_sequence<Row...>) noexcept {
  (runge_kutta_stage<M, Tableau, static_cast<int>(Row)>(s, w), ...);
}

}  // namespace tree_detail

// An explicit Runge-Kutta method (runge_kutta_tableaus.hpp) on the joint
// coordinates and their rates, y = (q, qd), y' = (qd, qdd(q, qd, t)): one
// recursion a stage, y(t + h) = y + h sum_i b_i k_i. rk4-tree steps by the
// classical method of order four, rk8-tree by Dormand and Prince's of order
// eight. Explicit, so nothing carries over between steps; s.qdd keeps the
// last stage's accelerations. Not symplectic, but at the steps it is run at
// its energy error is of the order of its position error
// (docs/staggered-tree.md, "rk4-tree" and "rk8-tree").
// (s) => (s at t + h). Allocates nothing, throws nothing, fixed work; on a
// non-finite result s keeps its old value.
template <class M, class Tableau>
StepStatus tree_runge_kutta_step(typename M::State& s, typename M::Workspace& w) noexcept {
  constexpr auto stages = std::make_index_sequence<Tableau::kStages>{};
  static_assert(M::kStages == Tableau::kStages, "the generated model's stages are the tableau's");
  tree_step_begin<M>(s, w);
  tree_detail::runge_kutta_stages<M, Tableau>(s, w, stages);
  for (std::size_t i = 0; i < s.q.size(); ++i) {
    s.q[i] = tree_detail::step_end<M, Tableau>(w.q0[i], w.stage_rates, i, stages);
    s.qd[i] = tree_detail::step_end<M, Tableau>(w.qd0[i], w.stage_accelerations, i, stages);
  }
  s.t = w.t0 + M::kStep;
  tree_step_close<M>(s, w);
  return tree_step_end<M>(s, w);
}

template <class M>
StepStatus tree_rk4_step(typename M::State& s, typename M::Workspace& w) noexcept {
  return tree_runge_kutta_step<M, ClassicalRungeKutta4>(s, w);
}

template <class M>
StepStatus tree_rk8_step(typename M::State& s, typename M::Workspace& w) noexcept {
  return tree_runge_kutta_step<M, DormandPrince8>(s, w);
}

}  // namespace mbrt::schemes
