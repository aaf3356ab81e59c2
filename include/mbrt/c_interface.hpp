// Copies between a generated model's C++ types and the plain C structs of its
// C interface (mbrt/model_c.h, <name>_c.h), member by member: the generated
// <name>_c.cpp calls to_c and from_c on each State member. Exact copies, so a
// step through the C interface gives the C++ step's state bit for bit.
#pragma once

#include <array>
#include <cstddef>

#include "mbrt/model_api.hpp"
#include "mbrt/model_c.h"

namespace mbrt::c_interface {

static_assert(MBRT_STEP_OK == static_cast<int>(StepStatus::ok));
static_assert(MBRT_STEP_NON_FINITE == static_cast<int>(StepStatus::non_finite));
static_assert(MBRT_STEP_NOT_POSITIVE == static_cast<int>(StepStatus::not_positive));

inline mbrt_step_status to_c(StepStatus s) noexcept { return static_cast<mbrt_step_status>(s); }

inline void to_c(double x, double& c) noexcept { c = x; }
inline void from_c(const double& c, double& x) noexcept { x = c; }

template <int N>
void to_c(const Eigen::Matrix<double, N, 1>& x, double (&c)[N]) noexcept {
  for (int i = 0; i < N; ++i) c[i] = x[i];
}
template <int N>
void from_c(const double (&c)[N], Eigen::Matrix<double, N, 1>& x) noexcept {
  for (int i = 0; i < N; ++i) x[i] = c[i];
}

inline void to_c(const RigidState& s, mbrt_rigid_state& c) noexcept {
  to_c(s.r, c.r);
  to_c(s.p, c.p);
  to_c(s.v, c.v);
  to_c(s.w, c.w);
}
inline void from_c(const mbrt_rigid_state& c, RigidState& s) noexcept {
  from_c(c.r, s.r);
  from_c(c.p, s.p);
  from_c(c.v, s.v);
  from_c(c.w, s.w);
}

inline void to_c(const ParticleState& s, mbrt_particle_state& c) noexcept {
  to_c(s.r, c.r);
  to_c(s.v, c.v);
}
inline void from_c(const mbrt_particle_state& c, ParticleState& s) noexcept {
  from_c(c.r, s.r);
  from_c(c.v, s.v);
}

inline void to_c(const RigidAcceleration& s, mbrt_rigid_acceleration& c) noexcept {
  to_c(s.a, c.a);
  to_c(s.alpha, c.alpha);
}
inline void from_c(const mbrt_rigid_acceleration& c, RigidAcceleration& s) noexcept {
  from_c(c.a, s.a);
  from_c(c.alpha, s.alpha);
}

inline mbrt_energy to_c(const Energy& e) noexcept { return {e.kinetic, e.potential}; }

inline mbrt_constraint_violation to_c(const ConstraintViolation& v) noexcept {
  return {v.position, v.velocity, v.acceleration};
}

inline void to_c(const JointReaction& r, mbrt_joint_reaction& c) noexcept {
  to_c(r.force, c.force);
  to_c(r.torque, c.torque);
  to_c(r.force_joint, c.force_joint);
  to_c(r.torque_joint, c.torque_joint);
}

// An array of any of the above onto a C array of the same length (declared
// last: the element copies are found where the template is defined).
template <class T, std::size_t N, class C>
void to_c(const std::array<T, N>& x, C (&c)[N]) noexcept {
  for (std::size_t i = 0; i < N; ++i) to_c(x[i], c[i]);
}
template <class T, std::size_t N, class C>
void from_c(const C (&c)[N], std::array<T, N>& x) noexcept {
  for (std::size_t i = 0; i < N; ++i) from_c(c[i], x[i]);
}

}  // namespace mbrt::c_interface
