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
// M is a generated model (struct Model in the model's source). It provides
//   types     State (t, q, qd, qdd, rigid, ...), Workspace, Dofs, HalfAngles;
//   constants kStep, kStages (recursions per step), kExternalLoads;
//   kernels   half_angles, body_states, kinematics, tree_loads,
//             joint_accelerations.
#pragma once

#include <cmath>

#include "mbrt/mul_add.hpp"
#include "mbrt/scheme.hpp"
#include "mbrt/body_state.hpp"
#include "mbrt/step_status.hpp"

namespace mbrt::schemes {

// The joint coordinates decide everything else (the rates after the last
// kick carry the accelerations); a body's velocity is where finite rates
// could still overflow.
template <class State>
bool tree_state_finite(const State& s) noexcept {
  double sum = 0.0;
  for (std::size_t i = 0; i < s.q.size(); ++i) sum += s.q[i] + s.qd[i];
  for (const RigidState& b : s.rigid) sum += b.v.sum();
  return std::isfinite(sum);
}

// (s with accelerations at t) => (s at t + h). Allocates nothing, throws
// nothing, fixed work; on a non-finite result s keeps its old value.
template <class M>
StepStatus tree_step(typename M::State& s, typename M::Workspace& w) noexcept {
  constexpr double h = M::kStep;
  w.t0 = s.t;
  w.q0 = s.q;
  w.qd0 = s.qd;
  w.qdd0 = s.qdd;
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
    M::joint_accelerations(s.q, w.half_angles, w.rates, w.k, w.l, s.qdd);
  }
  for (std::size_t i = 0; i < s.q.size(); ++i) s.qd[i] += (0.5 * h) * s.qdd[i];
  M::body_states(s.q, w.half_angles, s.qd, s);
  if (!tree_state_finite(s)) {
    s.t = w.t0;
    s.q = w.q0;
    s.qd = w.qd0;
    s.qdd = w.qdd0;
    M::half_angles(s.q, w.half_angles);
    M::body_states(s.q, w.half_angles, s.qd, s);
    return StepStatus::non_finite;
  }
  return StepStatus::ok;
}

}  // namespace mbrt::schemes
