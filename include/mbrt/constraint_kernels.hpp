// Constraint kernels: value, Jacobian with respect to u = [v; w_body] of each
// body, the explicit time derivative (drivers only) and the remaining
// acceleration terms, so that
//   phi_dot  = J1 u1 + J2 u2 + phi_t
//   phi_ddot = J1 u1' + J2 u2' + quad.
// Every joint is built from three primitives: a point fixed in a body, a unit
// vector fixed in a body, and scalar products of their differences.
#pragma once

#include <cmath>

#include "mbrt/body_state.hpp"

namespace mbrt {

// N rows over a body's C velocity columns: 6 in space, 3 in the plane (planar.hpp).
template <int N, int C = 6>
struct ConstraintRows {
  Eigen::Matrix<double, N, 1> phi;
  Eigen::Matrix<double, N, C> J1;
  Eigen::Matrix<double, N, C> J2;
  Eigen::Matrix<double, N, 1> quad;
  Eigen::Matrix<double, N, 1> phi_t = Eigen::Matrix<double, N, 1>::Zero();
};

// A world vector carried by a body (a point or a direction) with its first
// derivative, its Jacobian with respect to that body's u, and its second
// derivative at zero acceleration.
struct CarriedVector {
  Vec3 x;
  Vec3 x_dot;
  Mat36 J;
  Vec3 quad;
};

// Point with body-frame offset s from the COM: x = r + R s,
// x_dot = v + R (w x s), x_ddot = a + R (w' x s) + R (w x (w x s)).
inline CarriedVector carried_point(const BodyPose& pose, const BodyVelocity& vel, const Vec3& s) noexcept {
  CarriedVector c;
  const Vec3 w_x_s = vel.w.cross(s);
  c.x = pose.r + pose.R * s;
  c.x_dot = vel.v + pose.R * w_x_s;
  c.J.leftCols<3>().setIdentity();
  c.J.rightCols<3>() = -pose.R * skew(s);
  c.quad = pose.R * vel.w.cross(w_x_s);
  return c;
}

// Direction with body-frame components d: x = R d.
inline CarriedVector carried_direction(const BodyPose& pose, const BodyVelocity& vel, const Vec3& d) noexcept {
  CarriedVector c;
  const Vec3 w_x_d = vel.w.cross(d);
  c.x = pose.R * d;
  c.x_dot = pose.R * w_x_d;
  c.J.leftCols<3>().setZero();
  c.J.rightCols<3>() = -pose.R * skew(d);
  c.quad = pose.R * vel.w.cross(w_x_d);
  return c;
}

// Difference b - a of two carried vectors, each keeping its own body's Jacobian.
struct CarriedDifference {
  Vec3 x;
  Vec3 x_dot;
  Mat36 J1;  // of -a, body 1
  Mat36 J2;  // of b, body 2
  Vec3 quad;
};

inline CarriedDifference difference(const CarriedVector& a, const CarriedVector& b) noexcept {
  return {b.x - a.x, b.x_dot - a.x_dot, -a.J, b.J, b.quad - a.quad};
}

// One scalar constraint row over a body's C velocity columns.
template <int C>
struct ConstraintRow {
  double phi;
  Eigen::Matrix<double, 1, C> J1;
  Eigen::Matrix<double, 1, C> J2;
  double quad;
};
using ScalarRow = ConstraintRow<6>;

// The rows below take a CarriedVector and a CarriedDifference, or their
// planar counterparts (planar.hpp), whose Jacobians have C columns.

// Row: a . b, a carried by body 1, b by body 2 (perpendicularity of two axes).
template <class V, int C = decltype(V::J)::ColsAtCompileTime>
inline ConstraintRow<C> dot_row(const V& a, const V& b) noexcept {
  return {a.x.dot(b.x), b.x.transpose() * a.J, a.x.transpose() * b.J,
          a.quad.dot(b.x) + 2.0 * a.x_dot.dot(b.x_dot) + a.x.dot(b.quad)};
}

// Row: n . d, n carried by body 1, d = x2 - x1 (point 2 stays in a plane of body 1).
template <class V, class D, int C = decltype(V::J)::ColsAtCompileTime>
inline ConstraintRow<C> normal_dot_difference_row(const V& n, const D& d) noexcept {
  return {n.x.dot(d.x), d.x.transpose() * n.J + n.x.transpose() * d.J1, n.x.transpose() * d.J2,
          n.quad.dot(d.x) + 2.0 * n.x_dot.dot(d.x_dot) + n.x.dot(d.quad)};
}

// Row: the angle theta of body 2 about the axis a of body 1, measured from
// the triad (a, b, c) at t = 0 (cos theta = b1 . b2, sin theta = c1 . b2).
// theta' = a . (omega2 - omega1) in world axes; theta'' adds (omega1 x a) . omega2.
// phi is returned as theta only through wrap(): the caller subtracts the
// target angle and wraps, so multi-turn motion has no jump.
// cos and sin are kept (theta() is their atan2, whose instruction count
// depends on its argument): joint friction needs only small differences
// of theta, and its step does the same work every step.
struct AngleRow {
  double cos_theta, sin_theta;  // b1 . b2 and c1 . b2, in world axes
  Eigen::Matrix<double, 1, 6> J1;
  Eigen::Matrix<double, 1, 6> J2;
  double quad;
  double theta() const noexcept { return std::atan2(sin_theta, cos_theta); }  // in (-pi, pi]
};

inline AngleRow relative_angle_row(const BodyPose& p1, const BodyVelocity& v1, const Vec3& a1, const Vec3& b1,
                                   const Vec3& c1, const BodyPose& p2, const BodyVelocity& v2, const Vec3& b2) noexcept {
  const Vec3 a = p1.R * a1;
  const Vec3 b2w = p2.R * b2;
  AngleRow r;
  r.cos_theta = (p1.R * b1).dot(b2w);
  r.sin_theta = (p1.R * c1).dot(b2w);
  r.J1 << 0.0, 0.0, 0.0, -a1.transpose();
  r.J2 << 0.0, 0.0, 0.0, (p2.R.transpose() * a).transpose();
  const Vec3 omega1 = p1.R * v1.w, omega2 = p2.R * v2.w;
  r.quad = omega1.cross(a).dot(omega2);
  return r;
}

// Angle difference wrapped to (-pi, pi].
inline double wrap_angle(double x) noexcept { return std::remainder(x, 2.0 * 3.14159265358979323846); }

template <int N, int C>
inline void set_row(ConstraintRows<N, C>& rows, int i, const ConstraintRow<C>& r) noexcept {
  rows.phi[i] = r.phi;
  rows.J1.row(i) = r.J1;
  rows.J2.row(i) = r.J2;
  rows.quad[i] = r.quad;
}

// Rows 0..2: x2 - x1 = 0 (coincident points).
template <int N>
inline void coincidence_rows(const CarriedDifference& d, ConstraintRows<N>& rows) noexcept {
  rows.phi.template head<3>() = d.x;
  rows.J1.template topRows<3>() = d.J1;
  rows.J2.template topRows<3>() = d.J2;
  rows.quad.template head<3>() = d.quad;
}

}  // namespace mbrt
