// Planar coordinates for scenes that move in a plane of world coordinates
// (docs/specializations.md, "planar"): per body two coordinates in the
// plane and the rotation about its normal, velocities u = (v_i, v_j,
// omega_k), constraint rows of the in-plane directions only. The plane is
// named by its normal, world axis k (Normal: 0, 1 or 2); its coordinates are
// i = k + 1 and j = k + 2 (mod 3), so that (i, j, k) is right-handed and the
// formulas are those of the x-y plane. The step keeps the State's spatial
// fields and reads and writes their in-plane components: a rotation about k
// has Euler parameters (cos(theta/2), sin(theta/2) along k), and omega_k is
// the same in body and world axes. The generator gives every constant in
// plane coordinates (x, y, z) = (i, j, k). Every formula is the spatial one
// with the out-of-plane components zero, so both give the same trajectory to
// round-off.
#pragma once

#include <cmath>

#include "mbrt/body_state.hpp"
#include "mbrt/forces.hpp"
#include "mbrt/joints.hpp"

namespace mbrt {

using Vec2 = Eigen::Matrix<double, 2, 1>;
using Mat2 = Eigen::Matrix<double, 2, 2>;

struct PlanarPose {
  Vec2 r;
  Mat2 R;
};

struct PlanarVelocity {
  Vec2 v;
  double w;
};

struct PlanarMotion {
  const PlanarPose& pose;
  const PlanarVelocity& vel;
};

struct PlanarWrench {
  Vec2 f = Vec2::Zero();
  double tau = 0.0;
};

// A rigid body's mass and its moment of inertia about the body z axis.
struct PlanarInertia {
  double m;
  double J;
};

// N rows over (vx, vy, omega_z) of each body; phi_t is the drivers' -f'.
template <int N>
using PlanarRows = ConstraintRows<N, 3>;

// The in-plane components (i, j) of a world vector, or of a body-frame one
// of a body turned about k alone.
template <int Normal>
inline Vec2 in_plane(const Vec3& v) noexcept {
  return {v[(Normal + 1) % 3], v[(Normal + 2) % 3]};
}
template <int Normal>
inline void set_in_plane(const Vec2& x, Vec3& v) noexcept {
  v[(Normal + 1) % 3] = x.x();
  v[(Normal + 2) % 3] = x.y();
}

// R(p) of rotation.hpp for a rotation about k, its in-plane 2 x 2 block.
template <int Normal>
inline PlanarPose planar_pose_of(const RigidState& s) noexcept {
  const double e0 = s.p[0], ek = s.p[1 + Normal];
  PlanarPose pose{in_plane<Normal>(s.r), Mat2()};
  pose.R << 1.0 - 2.0 * (ek * ek), -2.0 * (e0 * ek), 2.0 * (e0 * ek), 1.0 - 2.0 * (ek * ek);
  return pose;
}
template <int Normal>
inline PlanarPose planar_pose_of(const ParticleState& s) noexcept {
  return {in_plane<Normal>(s.r), Mat2::Identity()};
}
template <int Normal>
inline PlanarVelocity planar_velocity_of(const RigidState& s) noexcept {
  return {in_plane<Normal>(s.v), s.w[Normal]};
}
template <int Normal>
inline PlanarVelocity planar_velocity_of(const ParticleState& s) noexcept {
  return {in_plane<Normal>(s.v), 0.0};
}
inline PlanarPose planar_ground_pose() noexcept { return {Vec2::Zero(), Mat2::Identity()}; }
inline PlanarVelocity planar_ground_velocity() noexcept { return {Vec2::Zero(), 0.0}; }

// (x_i, x_j, rotational) of a body's translational vector and the
// rotational component about the normal.
template <int Normal>
inline Vec3 planar_vector(const Vec3& translational, double rotational) noexcept {
  const Vec2 x = in_plane<Normal>(translational);
  return {x.x(), x.y(), rotational};
}

// u = (v_i, v_j, omega_k) of a body, read from and written to the State.
template <int Normal>
inline Vec3 planar_velocities(const RigidState& s) noexcept {
  return planar_vector<Normal>(s.v, s.w[Normal]);
}
template <int Normal>
inline Vec3 planar_velocities(const ParticleState& s) noexcept {
  return planar_vector<Normal>(s.v, 0.0);
}
template <int Normal>
inline void set_planar_velocities(const Vec3& u, RigidState& s) noexcept {
  set_in_plane<Normal>(u.head<2>(), s.v);
  s.w[Normal] = u.z();
}
template <int Normal>
inline void set_planar_velocities(const Vec3& u, ParticleState& s) noexcept {
  set_in_plane<Normal>(u.head<2>(), s.v);
}
template <int Normal>
inline Vec3 planar_accelerations(const RigidAcceleration& a) noexcept {
  return planar_vector<Normal>(a.a, a.alpha[Normal]);
}
template <int Normal>
inline Vec3 planar_accelerations(const Vec3& particle) noexcept {
  return planar_vector<Normal>(particle, 0.0);
}
template <int Normal>
inline void set_planar_accelerations(const Vec3& u, RigidAcceleration& a) noexcept {
  set_in_plane<Normal>(u.head<2>(), a.a);
  a.alpha[Normal] = u.z();
}
template <int Normal>
inline void set_planar_accelerations(const Vec3& u, Vec3& particle) noexcept {
  set_in_plane<Normal>(u.head<2>(), particle);
}

// advance_euler_parameters of rotation.hpp for w = omega along k: the Cayley
// increments and their products act on (e0, e_k) alone.
template <int Normal>
inline void advance_planar_rotation(EulerParameters& p, double omega, double h, int updates) noexcept {
  const double theta = (h / updates) * omega;
  const double x = 0.0625 * theta * theta;
  const double inv = 1.0 / (1.0 + x);
  const double c0 = (1.0 - x) * inv, ck = (0.5 * inv) * theta;
  double e0 = p[0], ek = p[1 + Normal];
  for (int k = 0; k < updates; ++k) {
    const double f0 = e0 * c0 - ek * ck;
    ek = e0 * ck + ek * c0;
    e0 = f0;
  }
  const double norm = std::sqrt(e0 * e0 + ek * ek);
  p[0] = e0 / norm;
  p[1 + Normal] = ek / norm;
}

// The explicit stage of the staggered step for one body (docs/staggered-pcst.md,
// eqs. 1-3) in its two halves: half a step of velocity, then a step of
// position and rotation, in the plane.
template <int Normal>
inline void planar_kick(RigidState& x, const RigidAcceleration& a, double h) noexcept {
  set_in_plane<Normal>(in_plane<Normal>(x.v) + (0.5 * h) * in_plane<Normal>(a.a), x.v);
  x.w[Normal] += (0.5 * h) * a.alpha[Normal];
}
template <int Normal>
inline void planar_kick(ParticleState& x, const Vec3& a, double h) noexcept {
  set_in_plane<Normal>(in_plane<Normal>(x.v) + (0.5 * h) * in_plane<Normal>(a), x.v);
}
template <int Normal>
inline void planar_drift(RigidState& x, double h, int updates) noexcept {
  set_in_plane<Normal>(in_plane<Normal>(x.r) + h * in_plane<Normal>(x.v), x.r);
  advance_planar_rotation<Normal>(x.p, x.w[Normal], h, updates);
}
template <int Normal>
inline void planar_drift(ParticleState& x, double h) noexcept {
  set_in_plane<Normal>(in_plane<Normal>(x.r) + h * in_plane<Normal>(x.v), x.r);
}

// Blajer's position correction of one body by dq = (dx, dy, dtheta): the
// spatial one's body-frame increment about the normal, cayley_increment of
// rotation.hpp acting on (e0, e_k).
template <int Normal>
inline void correct_planar_position(RigidState& x, const Vec3& dq) noexcept {
  set_in_plane<Normal>(in_plane<Normal>(x.r) + dq.head<2>(), x.r);
  advance_planar_rotation<Normal>(x.p, dq.z(), 1.0, 1);
}
template <int Normal>
inline void correct_planar_position(ParticleState& x, const Vec3& dq) noexcept {
  set_in_plane<Normal>(in_plane<Normal>(x.r) + dq.head<2>(), x.r);
}

// M^-1 F and M^-1 J^T of one body; a particle has no rotational row.
inline Vec3 inverse_mass_times(const PointMass& b, const PlanarWrench& w) noexcept { return {w.f.x() / b.m, w.f.y() / b.m, 0.0}; }
inline Vec3 inverse_mass_times(const PlanarInertia& b, const PlanarWrench& w) noexcept {
  return {w.f.x() / b.m, w.f.y() / b.m, w.tau / b.J};
}

template <int N>
inline Eigen::Matrix<double, 3, N> inverse_mass_times_transpose(const PointMass& b,
                                                                const Eigen::Matrix<double, N, 3>& J) noexcept {
  Eigen::Matrix<double, 3, N> x;
  x.template topRows<2>() = J.template leftCols<2>().transpose() / b.m;
  x.row(2).setZero();
  return x;
}

template <int N>
inline Eigen::Matrix<double, 3, N> inverse_mass_times_transpose(const PlanarInertia& b,
                                                                const Eigen::Matrix<double, N, 3>& J) noexcept {
  Eigen::Matrix<double, 3, N> x;
  x.template topRows<2>() = J.template leftCols<2>().transpose() / b.m;
  x.row(2) = J.col(2).transpose() / b.J;
  return x;
}

// A point or a direction carried by a body, with its first derivative, its
// Jacobian with respect to that body's u and its second derivative at zero
// acceleration: CarriedVector of constraint_kernels.hpp in the plane.
struct PlanarPoint {
  Vec2 x;
  Vec2 x_dot;
  Eigen::Matrix<double, 2, 3> J;
  Vec2 quad;
};

// Direction with body-frame components d (its x, y): x = R d,
// x_dot = omega R perp(d), x_ddot = omega' R perp(d) - omega^2 R d,
// perp(d) = (-d_y, d_x).
inline PlanarPoint planar_direction(const PlanarMotion& m, const Vec3& d) noexcept {
  const Vec2 r_perp = m.pose.R * Vec2(-d.y(), d.x());
  const Vec2 r_d = m.pose.R * d.head<2>();
  PlanarPoint p;
  p.x = r_d;
  p.x_dot = m.vel.w * r_perp;
  p.J << 0.0, 0.0, r_perp.x(), 0.0, 0.0, r_perp.y();
  p.quad = -(m.vel.w * m.vel.w) * r_d;
  return p;
}

// Point with body-frame offset s (its x, y) from the COM: x = r + R s,
// x_dot = v + omega R perp(s), x_ddot = a + omega' R perp(s) - omega^2 R s.
inline PlanarPoint planar_point(const PlanarMotion& m, const Vec3& s) noexcept {
  PlanarPoint p = planar_direction(m, s);
  p.x += m.pose.r;
  p.x_dot += m.vel.v;
  p.J.leftCols<2>().setIdentity();
  return p;
}

// add_point_force of forces.hpp in the plane: f (world) at body point s
// adds its moment about z.
inline void add_point_force(PlanarWrench& w, const PlanarPose& pose, const Vec3& s, const Vec2& f) noexcept {
  const Vec2 f_body = pose.R.transpose() * f;
  w.f += f;
  w.tau += s.x() * f_body.y() - s.y() * f_body.x();
}

struct PlanarSpringDamperForce {
  Vec2 f2;        // force on body 2 at its point (body 1 gets -f2), world
  double energy;  // stored elastic energy
};

// spring_damper of forces.hpp with both points in one plane z = const.
inline PlanarSpringDamperForce planar_spring_damper(const SpringDamper& e, const PlanarMotion& m1,
                                                    const PlanarMotion& m2) noexcept {
  const PlanarPoint p1 = planar_point(m1, e.s1), p2 = planar_point(m2, e.s2);
  const Vec2 d = p2.x - p1.x;
  const double l = d.norm();
  const double stretch = l - e.rest_length;
  PlanarSpringDamperForce out{Vec2::Zero(), 0.5 * e.stiffness * stretch * stretch};
  if (l > 1e-12) {  // coincident points have no line of action
    const Vec2 n = d / l;
    const double tension = e.stiffness * stretch + e.damping * n.dot(p2.x_dot - p1.x_dot);
    out.f2 = -tension * n;
  }
  return out;
}

// One row over (vx, vy, omega_z) of each body.
using PlanarRow = ConstraintRow<3>;

// Difference x2 - x1 of the joint points, each keeping its own body's
// Jacobian: CarriedDifference of joint_points (joints.hpp) in the plane.
struct PlanarDifference {
  Vec2 x;
  Vec2 x_dot;
  Eigen::Matrix<double, 2, 3> J1;  // of -x1, body 1
  Eigen::Matrix<double, 2, 3> J2;  // of x2, body 2
  Vec2 quad;
};

inline PlanarDifference planar_joint_points(const JointFrame& f, const PlanarMotion& m1, const PlanarMotion& m2) noexcept {
  const PlanarPoint a = planar_point(m1, f.s1), b = planar_point(m2, f.s2);
  return {b.x - a.x, b.x_dot - a.x_dot, -a.J, b.J, b.quad - a.quad};
}

// Revolute about z (and spherical, whose other rotations the scene leaves at
// rest): the joint points coincide in x and y, rows 0 and 1 of the spatial
// joint.
inline PlanarRows<2> planar_revolute(const JointFrame& f, const PlanarMotion& m1, const PlanarMotion& m2) noexcept {
  const PlanarDifference d = planar_joint_points(f, m1, m2);
  return {d.x, d.J1, d.J2, d.quad};
}

// distance of joints.hpp with both points in one plane z = const.
inline PlanarRows<1> planar_distance(const JointFrame& f, const PlanarMotion& m1, const PlanarMotion& m2) noexcept {
  return detail::distance_rows(planar_joint_points(f, m1, m2), f.length);
}

// Which vector of a prismatic joint's triad (a, b, c) lies in the plane with
// the axis a; the other one is the plane's normal (codegen/plan/planar_scene.cpp).
enum class InPlane { b, c };

// prismatic of joints.hpp with its axis in the plane: its two rows that do
// not involve the normal, a1 . e2 (no rotation about the normal) and e1 . d
// (no offset across the axis), e the triad vector in the plane. They are the
// spatial rows 0 and 2 for e = b, 1 and 3 for e = c; the other three stay
// zero in the plane.
template <InPlane E>
inline PlanarRows<2> planar_prismatic(const JointFrame& f, const PlanarMotion& m1, const PlanarMotion& m2) noexcept {
  const Vec3& e1 = E == InPlane::b ? f.b1 : f.c1;
  const Vec3& e2 = E == InPlane::b ? f.b2 : f.c2;
  PlanarRows<2> rows;
  set_row(rows, 0, dot_row(planar_direction(m1, f.a1), planar_direction(m2, e2)));
  set_row(rows, 1, normal_dot_difference_row(planar_direction(m1, e1), planar_joint_points(f, m1, m2)));
  return rows;
}

// revolute_coordinate of joint_coordinates.hpp on a revolute joint about
// +-z: the angle from the in-plane b and c of its triad. The axis
// a = (0, 0, a_z) keeps its direction, so theta' = a_z (omega2 - omega1).
inline JointCoordinate planar_revolute_coordinate(const JointFrame& f, const PlanarMotion& m1,
                                                  const PlanarMotion& m2) noexcept {
  const Vec2 b2 = m2.pose.R * f.b2.head<2>();
  const double theta = std::atan2((m1.pose.R * f.c1.head<2>()).dot(b2), (m1.pose.R * f.b1.head<2>()).dot(b2));
  return {theta, f.a1.z() * (m2.vel.w - m1.vel.w)};
}

// prismatic_coordinate of joint_coordinates.hpp with the axis in the plane:
// d = a1 . (x2 - x1), d' = a1' . (x2 - x1) + a1 . (x2' - x1').
inline JointCoordinate planar_prismatic_coordinate(const JointFrame& f, const PlanarMotion& m1,
                                                   const PlanarMotion& m2) noexcept {
  const PlanarPoint a = planar_direction(m1, f.a1);
  const PlanarDifference d = planar_joint_points(f, m1, m2);
  return {a.x.dot(d.x), a.x_dot.dot(d.x) + a.x.dot(d.x_dot)};
}

// Drivers: detail::driven of joints.hpp adds phi_t = -f' and -f'' to quad.

// joint_angle_driver of joints.hpp on a revolute joint about +-z; quad is
// zero since the axis keeps its direction.
inline PlanarRows<1> planar_joint_angle_driver(const JointFrame& f, const PlanarMotion& m1, const PlanarMotion& m2,
                                               const TimeValue& target) noexcept {
  const double theta = planar_revolute_coordinate(f, m1, m2).position;
  const double a_z = f.a1.z();
  return detail::driven(PlanarRow{wrap_angle(theta - target.f), {0.0, 0.0, -a_z}, {0.0, 0.0, a_z}, 0.0}, target);
}

// joint_distance_driver of joints.hpp on a prismatic joint whose axis lies in the plane.
inline PlanarRows<1> planar_joint_distance_driver(const JointFrame& f, const PlanarMotion& m1, const PlanarMotion& m2,
                                                  const TimeValue& target) noexcept {
  PlanarRow r = normal_dot_difference_row(planar_direction(m1, f.a1), planar_joint_points(f, m1, m2));
  r.phi -= target.f;
  return detail::driven(r, target);
}

// distance_driver of joints.hpp with both points in one plane z = const.
inline PlanarRows<1> planar_distance_driver(const JointFrame& f, const PlanarMotion& m1, const PlanarMotion& m2,
                                            const TimeValue& target) noexcept {
  return detail::distance_driven(planar_joint_points(f, m1, m2), target);
}

}  // namespace mbrt
