// Holonomic joints as compositions of the kernels in constraint_kernels.hpp.
// Frames are constant body-frame data computed by the generator from the
// model's world description at t = 0.
#pragma once

#include "mbrt/constraint_kernels.hpp"
#include "mbrt/time_functions.hpp"

namespace mbrt {

// Body-frame joint data. Triad (a, b, c) is orthonormal with a along the
// joint axis; a1, b1, c1 are its components in body 1, a2, b2, c2 the same
// world triad in body 2 at t = 0 (for universal joints a2 is the second axis).
struct JointFrame {
  Vec3 s1, s2;       // joint point on each body, from the COM
  Vec3 a1, b1, c1;
  Vec3 a2, b2, c2;
  double length;     // distance joints only
  double pitch;      // screw joints: translation per radian (lead / 2 pi)
};

struct BodyMotion {
  const BodyPose& pose;
  const BodyVelocity& vel;
};

namespace detail {
inline CarriedDifference joint_points(const JointFrame& f, const BodyMotion& m1, const BodyMotion& m2) noexcept {
  return difference(carried_point(m1.pose, m1.vel, f.s1), carried_point(m2.pose, m2.vel, f.s2));
}

template <int N>
inline void add_dot_row(ConstraintRows<N>& rows, int i, const CarriedVector& a, const CarriedVector& b) noexcept {
  set_row(rows, i, dot_row(a, b));
}

template <int N>
inline void add_plane_row(ConstraintRows<N>& rows, int i, const CarriedVector& n, const CarriedDifference& d) noexcept {
  set_row(rows, i, normal_dot_difference_row(n, d));
}
}  // namespace detail

// Spherical: the joint points coincide (3 rows).
inline ConstraintRows<3> spherical(const JointFrame& f, const BodyMotion& m1, const BodyMotion& m2) noexcept {
  ConstraintRows<3> rows;
  coincidence_rows(detail::joint_points(f, m1, m2), rows);
  return rows;
}

// Revolute: spherical plus the axis of body 1 perpendicular to b and c of body 2 (5 rows).
inline ConstraintRows<5> revolute(const JointFrame& f, const BodyMotion& m1, const BodyMotion& m2) noexcept {
  ConstraintRows<5> rows;
  coincidence_rows(detail::joint_points(f, m1, m2), rows);
  const CarriedVector a1 = carried_direction(m1.pose, m1.vel, f.a1);
  detail::add_dot_row(rows, 3, a1, carried_direction(m2.pose, m2.vel, f.b2));
  detail::add_dot_row(rows, 4, a1, carried_direction(m2.pose, m2.vel, f.c2));
  return rows;
}

// Universal: spherical plus axis 1 (in body 1) perpendicular to axis 2 (in body 2) (4 rows).
inline ConstraintRows<4> universal(const JointFrame& f, const BodyMotion& m1, const BodyMotion& m2) noexcept {
  ConstraintRows<4> rows;
  coincidence_rows(detail::joint_points(f, m1, m2), rows);
  detail::add_dot_row(rows, 3, carried_direction(m1.pose, m1.vel, f.a1), carried_direction(m2.pose, m2.vel, f.a2));
  return rows;
}

namespace detail {
// Axes parallel and the point of body 2 on the axis line of body 1 (4 rows).
template <int N>
inline void cylindrical_rows(const JointFrame& f, const BodyMotion& m1, const BodyMotion& m2,
                             ConstraintRows<N>& rows) noexcept {
  const CarriedDifference d = joint_points(f, m1, m2);
  const CarriedVector a1 = carried_direction(m1.pose, m1.vel, f.a1);
  add_dot_row(rows, 0, a1, carried_direction(m2.pose, m2.vel, f.b2));
  add_dot_row(rows, 1, a1, carried_direction(m2.pose, m2.vel, f.c2));
  add_plane_row(rows, 2, carried_direction(m1.pose, m1.vel, f.b1), d);
  add_plane_row(rows, 3, carried_direction(m1.pose, m1.vel, f.c1), d);
}
}  // namespace detail

// Cylindrical: slides along and turns about the axis (4 rows).
inline ConstraintRows<4> cylindrical(const JointFrame& f, const BodyMotion& m1, const BodyMotion& m2) noexcept {
  ConstraintRows<4> rows;
  detail::cylindrical_rows(f, m1, m2, rows);
  return rows;
}

// Prismatic: cylindrical plus no rotation about the axis, b1 . c2 = 0 (5 rows).
inline ConstraintRows<5> prismatic(const JointFrame& f, const BodyMotion& m1, const BodyMotion& m2) noexcept {
  ConstraintRows<5> rows;
  detail::cylindrical_rows(f, m1, m2, rows);
  detail::add_dot_row(rows, 4, carried_direction(m1.pose, m1.vel, f.b1), carried_direction(m2.pose, m2.vel, f.c2));
  return rows;
}

// Fixed: spherical plus the two triads kept aligned (6 rows).
inline ConstraintRows<6> fixed(const JointFrame& f, const BodyMotion& m1, const BodyMotion& m2) noexcept {
  ConstraintRows<6> rows;
  coincidence_rows(detail::joint_points(f, m1, m2), rows);
  const CarriedVector a1 = carried_direction(m1.pose, m1.vel, f.a1);
  const CarriedVector c2 = carried_direction(m2.pose, m2.vel, f.c2);
  detail::add_dot_row(rows, 3, a1, carried_direction(m2.pose, m2.vel, f.b2));
  detail::add_dot_row(rows, 4, a1, c2);
  detail::add_dot_row(rows, 5, carried_direction(m1.pose, m1.vel, f.b1), c2);
  return rows;
}

// Screw: cylindrical plus translation along the axis = pitch x rotation
// about it (Lidstrom 2012, Math. Mech. Solids 17(3), 209-242), phi = pitch wrap(d_a / pitch - theta), which is
// d_a - pitch theta on the branch nearest the current translation (5 rows).
inline ConstraintRows<5> screw(const JointFrame& f, const BodyMotion& m1, const BodyMotion& m2) noexcept {
  ConstraintRows<5> rows;
  detail::cylindrical_rows(f, m1, m2, rows);
  const ScalarRow slide = normal_dot_difference_row(carried_direction(m1.pose, m1.vel, f.a1), detail::joint_points(f, m1, m2));
  const AngleRow turn = relative_angle_row(m1.pose, m1.vel, f.a1, f.b1, f.c1, m2.pose, m2.vel, f.b2);
  set_row(rows, 4,
          {f.pitch * wrap_angle(slide.phi / f.pitch - turn.theta()), slide.J1 - f.pitch * turn.J1,
           slide.J2 - f.pitch * turn.J2, slide.quad - f.pitch * turn.quad});
  return rows;
}

// Planar: body 2 keeps the plane through the joint point with normal a of
// body 1, and turns only about a (3 rows).
inline ConstraintRows<3> planar(const JointFrame& f, const BodyMotion& m1, const BodyMotion& m2) noexcept {
  ConstraintRows<3> rows;
  const CarriedVector a1 = carried_direction(m1.pose, m1.vel, f.a1);
  detail::add_dot_row(rows, 0, a1, carried_direction(m2.pose, m2.vel, f.b2));
  detail::add_dot_row(rows, 1, a1, carried_direction(m2.pose, m2.vel, f.c2));
  detail::add_plane_row(rows, 2, a1, detail::joint_points(f, m1, m2));
  return rows;
}

// Drivers: one rheonomic row each, phi(q) - f(t) = 0, so phi_t = -f' and
// quad gains -f''.
namespace detail {
template <int C>
inline ConstraintRows<1, C> driven(const ConstraintRow<C>& r, const TimeValue& f) noexcept {
  ConstraintRows<1, C> rows;
  set_row(rows, 0, {r.phi, r.J1, r.J2, r.quad - f.ddf});
  rows.phi_t[0] = -f.df;
  return rows;
}
}  // namespace detail

// Prescribed angle of body 2 about the joint axis of body 1, from t = 0.
inline ConstraintRows<1> joint_angle_driver(const JointFrame& f, const BodyMotion& m1, const BodyMotion& m2,
                                            const TimeValue& target) noexcept {
  const AngleRow turn = relative_angle_row(m1.pose, m1.vel, f.a1, f.b1, f.c1, m2.pose, m2.vel, f.b2);
  return detail::driven(ScalarRow{wrap_angle(turn.theta() - target.f), turn.J1, turn.J2, turn.quad}, target);
}

// Prescribed displacement of the joint point of body 2 along the axis of body 1, from t = 0.
inline ConstraintRows<1> joint_distance_driver(const JointFrame& f, const BodyMotion& m1, const BodyMotion& m2,
                                               const TimeValue& target) noexcept {
  ScalarRow r = normal_dot_difference_row(carried_direction(m1.pose, m1.vel, f.a1), detail::joint_points(f, m1, m2));
  r.phi -= target.f;
  return detail::driven(r, target);
}

namespace detail {
// |x2 - x1| - f(t) from the points' difference d (a CarriedDifference, or
// planar.hpp's PlanarDifference).
template <class D, int C = decltype(D::J1)::ColsAtCompileTime>
inline ConstraintRows<1, C> distance_driven(const D& d, const TimeValue& target) noexcept {
  const double l = d.x.norm();
  const auto n = (d.x / l).eval();
  const double along = n.dot(d.x_dot);
  return driven(ConstraintRow<C>{l - target.f, n.transpose() * d.J1, n.transpose() * d.J2,
                                 (d.x_dot.squaredNorm() - along * along) / l + n.dot(d.quad)},
                target);
}
}  // namespace detail

// Prescribed distance |x2 - x1| between a point of each body.
inline ConstraintRows<1> distance_driver(const JointFrame& f, const BodyMotion& m1, const BodyMotion& m2,
                                         const TimeValue& target) noexcept {
  return detail::distance_driven(detail::joint_points(f, m1, m2), target);
}

namespace detail {
// The distance row from the points' difference d (a CarriedDifference, or
// planar.hpp's PlanarDifference).
template <class D, int C = decltype(D::J1)::ColsAtCompileTime>
inline ConstraintRows<1, C> distance_rows(const D& d, double length) noexcept {
  ConstraintRows<1, C> rows;
  const double inv_l = 1.0 / length;
  rows.phi[0] = 0.5 * inv_l * (d.x.squaredNorm() - length * length);
  rows.J1.row(0) = inv_l * d.x.transpose() * d.J1;
  rows.J2.row(0) = inv_l * d.x.transpose() * d.J2;
  rows.quad[0] = inv_l * (d.x_dot.squaredNorm() + d.x.dot(d.quad));
  return rows;
}
}  // namespace detail

// Distance: (|x2 - x1|^2 - L^2) / (2 L) = 0, which has units of length and
// equals |x2 - x1| - L to first order (1 row).
inline ConstraintRows<1> distance(const JointFrame& f, const BodyMotion& m1, const BodyMotion& m2) noexcept {
  return detail::distance_rows(detail::joint_points(f, m1, m2), f.length);
}

}  // namespace mbrt
