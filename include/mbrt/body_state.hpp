// Per-body state, pose and velocity as the step sees them:
// COM position r and velocity v in world axes; Euler parameters p (body to
// world); angular velocity w in body axes. Particles carry no rotational state.
#pragma once

#include "mbrt/rotation.hpp"

namespace mbrt {

struct RigidState {
  Vec3 r;
  EulerParameters p;
  Vec3 v;
  Vec3 w;
};

struct ParticleState {
  Vec3 r;
  Vec3 v;
};

// Accelerations of the last evaluation, kept between steps (first stage of a
// step reuses the last stage of the previous one).
struct RigidAcceleration {
  Vec3 a;      // COM, world
  Vec3 alpha;  // angular, body
};

// Where a body is and how it moves, in the form the joint kernels take.
// Particles and ground use R = I and w = 0.
struct BodyPose {
  Vec3 r;
  Mat3 R;
};

struct BodyVelocity {
  Vec3 v;
  Vec3 w;
};

inline BodyPose pose_of(const RigidState& s) noexcept { return {s.r, rotation_matrix(s.p)}; }
inline BodyPose pose_of(const ParticleState& s) noexcept { return {s.r, Mat3::Identity()}; }
inline BodyVelocity velocity_of(const RigidState& s) noexcept { return {s.v, s.w}; }
inline BodyVelocity velocity_of(const ParticleState& s) noexcept { return {s.v, Vec3::Zero()}; }
inline BodyPose ground_pose() noexcept { return {Vec3::Zero(), Mat3::Identity()}; }
inline BodyVelocity ground_velocity() noexcept { return {Vec3::Zero(), Vec3::Zero()}; }

// Mass properties, one type per specialization: the inverse-mass products
// skip the rotational part for particles and the off-diagonal inertia
// products for principal-axis bodies.
struct PointMass {
  double m;
};

struct PrincipalInertia {
  double m;
  Vec3 J;  // diagonal of the inertia about the COM, body axes
};

struct FullInertia {
  double m;
  Mat3 J;
  Mat3 J_inv;
  Vec3 principal_moments;
  EulerParameters principal_axes;  // principal to body axes (the free rotation works in them)
};

inline Vec3 inertia_times(const PrincipalInertia& b, const Vec3& w) noexcept { return b.J.cwiseProduct(w); }
inline Vec3 inertia_times(const FullInertia& b, const Vec3& w) noexcept { return b.J * w; }
inline Vec3 inverse_inertia_times(const PrincipalInertia& b, const Vec3& t) noexcept {
  return t.cwiseQuotient(b.J);
}
inline Vec3 inverse_inertia_times(const FullInertia& b, const Vec3& t) noexcept { return b.J_inv * t; }

}  // namespace mbrt
