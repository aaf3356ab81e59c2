// Nonholonomic contacts between a body (body 2) and the ground plane: rows
// on velocities, A u = 0, with phi = 0 (the rolling disk's first row, the
// contact height, is holonomic). Same interface as the joints, so every
// scheme carries them: phi_ddot = J2 u2' + quad.
#pragma once

#include <cmath>

#include "mbrt/joints.hpp"

namespace mbrt {

namespace detail {
template <int N>
inline void set_velocity_row(ConstraintRows<N>& rows, int i, const Vec3& dir, const Mat36& J, double quad) noexcept {
  rows.phi[i] = 0.0;
  rows.J1.row(i).setZero();  // body 1 is the ground
  rows.J2.row(i) = dir.transpose() * J;
  rows.quad[i] = quad;
}
}  // namespace detail

// Thin disk of radius f.length rolling without slip on the plane through
// f.s1 with unit normal f.c1 (tangents f.a1, f.b1, world); f.a2: the disk's
// symmetry axis in body axes. Contact point C = r + rho d with d the unit
// vector in the disk's plane pointing down the plane normal. Row 0: the
// contact height (holonomic); rows 1, 2: the material point at C has no
// tangential velocity. All three rows are the material point's velocity
// v + omega x (rho d) along c1, a1, b1; their acceleration term is
// omega x (rho d_dot), d_dot the contact point's motion around the rim.
inline ConstraintRows<3> rolling_disk(const JointFrame& f, const BodyMotion& ground, const BodyMotion& disk) noexcept {
  (void)ground;
  const Vec3& e = f.c1;
  const double rho = f.length;
  const Vec3 n = disk.pose.R * f.a2;
  const Vec3 omega = disk.pose.R * disk.vel.w;
  const Vec3 u = e - e.dot(n) * n;
  const double len = u.norm();
  const Vec3 d = -u / len;
  const CarriedVector c = carried_point(disk.pose, disk.vel, disk.pose.R.transpose() * (rho * d));
  const Vec3 n_dot = omega.cross(n);
  const Vec3 u_dot = -(e.dot(n_dot) * n + e.dot(n) * n_dot);
  const Vec3 d_dot = -(u_dot - d * d.dot(u_dot)) / len;
  const Vec3 quad = omega.cross(rho * d_dot);
  ConstraintRows<3> rows;
  detail::set_velocity_row(rows, 0, e, c.J, e.dot(quad));
  rows.phi[0] = e.dot(c.x - f.s1);
  detail::set_velocity_row(rows, 1, f.a1, c.J, f.a1.dot(quad));
  detail::set_velocity_row(rows, 2, f.b1, c.J, f.b1.dot(quad));
  return rows;
}

// Sphere of radius f.length whose centre sits at f.s2 (body axes, off the
// COM for the "bowling ball") rolling without slip on the plane through f.s1
// with unit normal f.c1 (tangents f.a1, f.b1). The contact point is the
// centre minus radius times the normal. Row 0: the centre's height above the
// plane minus the radius (holonomic); rows 1, 2: no tangential velocity of
// the material point at the contact. Acceleration term:
// omega x (omega x (centre - COM)).
inline ConstraintRows<3> rolling_ball(const JointFrame& f, const BodyMotion& ground, const BodyMotion& ball) noexcept {
  (void)ground;
  const Vec3& e = f.c1;
  const CarriedVector centre = carried_point(ball.pose, ball.vel, f.s2);
  const Vec3 offset = centre.x - ball.pose.r;  // world, from the COM
  const CarriedVector c = carried_point(ball.pose, ball.vel, ball.pose.R.transpose() * (offset - f.length * e));
  const Vec3 omega = ball.pose.R * ball.vel.w;
  const Vec3 quad = omega.cross(omega.cross(offset));
  ConstraintRows<3> rows;
  detail::set_velocity_row(rows, 0, e, c.J, e.dot(quad));
  rows.phi[0] = e.dot(centre.x - f.s1) - f.length;
  detail::set_velocity_row(rows, 1, f.a1, c.J, f.a1.dot(quad));
  detail::set_velocity_row(rows, 2, f.b1, c.J, f.b1.dot(quad));
  return rows;
}

// Knife edge: the point f.s2 of the body (body axes) moves only along the
// edge f.a2 (body axes) within the plane of unit normal f.c1 (world):
// (n x edge) . v_P = 0.
inline ConstraintRows<1> knife_edge(const JointFrame& f, const BodyMotion& ground, const BodyMotion& body) noexcept {
  (void)ground;
  const Vec3& e = f.c1;
  const CarriedVector p = carried_point(body.pose, body.vel, f.s2);
  const CarriedVector edge = carried_direction(body.pose, body.vel, f.a2);
  const Vec3 side = e.cross(edge.x);
  ConstraintRows<1> rows;
  detail::set_velocity_row(rows, 0, side, p.J, e.cross(edge.x_dot).dot(p.x_dot) + side.dot(p.quad));
  return rows;
}

// The velocity of point f.s1 of body 1 points towards point f.s2 of body 2,
// in the plane of unit normal f.c1 (Dopico et al. 2014's two masses):
// (n x (x2 - x1)) . v1 = 0. Body 2's velocity does not enter the row.
inline ConstraintRows<1> velocity_toward(const JointFrame& f, const BodyMotion& m1, const BodyMotion& m2) noexcept {
  const CarriedVector a = carried_point(m1.pose, m1.vel, f.s1);
  const CarriedVector b = carried_point(m2.pose, m2.vel, f.s2);
  const Vec3 side = f.c1.cross(b.x - a.x);
  ConstraintRows<1> rows;
  rows.phi[0] = 0.0;
  rows.J1.row(0) = side.transpose() * a.J;
  rows.J2.row(0).setZero();
  rows.quad[0] = f.c1.cross(b.x_dot - a.x_dot).dot(a.x_dot) + side.dot(a.quad);
  return rows;
}

}  // namespace mbrt
