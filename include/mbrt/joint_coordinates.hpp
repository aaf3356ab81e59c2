// Joint coordinates for output signals: the angle of a revolute joint or the
// slide of a prismatic joint, measured from the configuration at t = 0 like
// the drivers (joints.hpp), and their rates.
#pragma once

#include <cmath>

#include "mbrt/joints.hpp"

namespace mbrt {

struct JointCoordinate {
  double position;  // rad or m
  double velocity;  // rad/s or m/s
};

namespace detail {
inline Vec6 generalized_velocity(const BodyVelocity& v) noexcept {
  Vec6 u;
  u << v.v, v.w;
  return u;
}

template <class Row>
inline double rate_of(const Row& r, const BodyMotion& m1, const BodyMotion& m2) noexcept {
  return r.J1.dot(generalized_velocity(m1.vel)) + r.J2.dot(generalized_velocity(m2.vel));
}
}  // namespace detail

// A joint coordinate's row, rate = J1 u1 + J2 u2 with u = [v; w_body] of
// each body (what joint friction acts along), and where the joint is: a
// revolute joint's cos and sin of its angle (unnormalized, AngleRow), a
// prismatic joint's slide (and 0).
struct JointRow {
  Eigen::Vector2d at;
  Eigen::Matrix<double, 1, 6> J1, J2;
};

// Angle of body 2 about the axis of body 1.
inline JointRow revolute_row(const JointFrame& f, const BodyMotion& m1, const BodyMotion& m2) noexcept {
  const AngleRow r = relative_angle_row(m1.pose, m1.vel, f.a1, f.b1, f.c1, m2.pose, m2.vel, f.b2);
  return {Eigen::Vector2d(r.cos_theta, r.sin_theta), r.J1, r.J2};
}

// Displacement of the joint point of body 2 along the axis of body 1.
inline JointRow prismatic_row(const JointFrame& f, const BodyMotion& m1, const BodyMotion& m2) noexcept {
  const ScalarRow r =
      normal_dot_difference_row(carried_direction(m1.pose, m1.vel, f.a1), detail::joint_points(f, m1, m2));
  return {Eigen::Vector2d(r.phi, 0.0), r.J1, r.J2};
}

// How far a joint has moved from `to` back to `from` (from - to): the
// slide's difference, or the sine of the angle's (the angle itself to
// O(d^3): for the small offsets of a held joint; no atan2, whose work
// depends on its argument).
inline double joint_offset(const JointRow& from, const JointRow& to, bool revolute) noexcept {
  if (!revolute) return from.at[0] - to.at[0];
  const double cross = from.at[1] * to.at[0] - from.at[0] * to.at[1];
  return cross / std::sqrt(from.at.squaredNorm() * to.at.squaredNorm());
}

// Angle of body 2 about the axis of body 1, in (-pi, pi].
inline JointCoordinate revolute_coordinate(const JointFrame& f, const BodyMotion& m1, const BodyMotion& m2) noexcept {
  const AngleRow r = relative_angle_row(m1.pose, m1.vel, f.a1, f.b1, f.c1, m2.pose, m2.vel, f.b2);
  return {r.theta(), detail::rate_of(r, m1, m2)};
}

// Displacement of the joint point of body 2 along the axis of body 1.
inline JointCoordinate prismatic_coordinate(const JointFrame& f, const BodyMotion& m1, const BodyMotion& m2) noexcept {
  const ScalarRow r =
      normal_dot_difference_row(carried_direction(m1.pose, m1.vel, f.a1), detail::joint_points(f, m1, m2));
  return {r.phi, detail::rate_of(r, m1, m2)};
}

}  // namespace mbrt
