// The pieces of a contact (docs/contact.md): its constant data, the body
// state it acts on, its geometry at the current positions, and what an
// impulse at it does to the body's velocity and position.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

#include "mbrt/rotation.hpp"
#include "mbrt/types.hpp"

namespace mbrt {

// A contact's constant data (generated from the model file).
struct ContactPoint {
  int body;                         // its body's index in the model's body vectors
  bool jointed;                     // its body is in a joint or driver
  Vec3 offset;                      // body axes: from the COM to the point, or to the sphere's centre
  double radius;                    // sphere; 0 for a point
  Vec3 plane_point;                 // world
  Vec3 normal, tangent1, tangent2;  // world, right-handed, normal out of the ground
  double inverse_mass;
  Mat3 inverse_inertia;             // body axes; zero for a particle
  double mu_static, mu_kinetic, restitution;
};

// Where a contact's body keeps its state; p and w are null for a particle.
struct ContactBody {
  Vec3* r;
  EulerParameters* p;
  Vec3* v;
  Vec3* w;
};

namespace contact_detail {

// max(x, 0) and max(x, floor) without a branch (std::max may compile to
// one): the contact step does the same work whatever the contacts do.
inline double positive_part(double x) noexcept { return 0.5 * (x + std::abs(x)); }
inline double at_least(double x, double floor) noexcept { return floor + positive_part(x - floor); }

// A contact's geometry at the current positions: the direction of each
// impulse component in body-axes angular terms (rho x R^T e), and the gap.
struct Frame {
  Mat3 rt;             // R^T (identity for a particle)
  Vec3 rho;            // body axes: from the COM to the contact point
  std::array<Vec3, 3> arm;  // rho x R^T e_k, k = normal, tangent1, tangent2
  double gap;          // distance of the contact point above the plane (m)
};

inline Frame frame_of(const ContactPoint& c, const ContactBody& b) noexcept {
  Frame f;
  f.rt = b.p ? Mat3(rotation_matrix(*b.p).transpose()) : Mat3(Mat3::Identity());
  f.rho = c.offset - c.radius * (f.rt * c.normal);
  const Vec3 point = *b.r + f.rt.transpose() * f.rho;
  f.gap = c.normal.dot(point - c.plane_point);
  const Vec3* e[3] = {&c.normal, &c.tangent1, &c.tangent2};
  for (int k = 0; k < 3; ++k) f.arm[k] = b.p ? Vec3(f.rho.cross(f.rt * *e[k])) : Vec3(Vec3::Zero());
  return f;
}

// The contact point's velocity along (normal, tangent1, tangent2).
inline Vec3 point_velocity(const ContactPoint& c, const ContactBody& b, const Frame& f) noexcept {
  Vec3 u(c.normal.dot(*b.v), c.tangent1.dot(*b.v), c.tangent2.dot(*b.v));
  if (b.w) {
    for (int k = 0; k < 3; ++k) u[k] += f.arm[k].dot(*b.w);
  }
  return u;
}

// M^-1 J^T dP for an impulse dP (normal, tangent1, tangent2) at the point:
// the body's translation (world) and rotation (body axes) parts. The same
// directions serve a velocity change (an impulse) and a displacement (a
// position impulse).
inline Vec3 linear_response(const ContactPoint& c, const Vec3& dp) noexcept {
  return c.inverse_mass * (dp[0] * c.normal + dp[1] * c.tangent1 + dp[2] * c.tangent2);
}
inline Vec3 angular_response(const ContactPoint& c, const Frame& f, const Vec3& dp) noexcept {
  return c.inverse_inertia * (dp[0] * f.arm[0] + dp[1] * f.arm[1] + dp[2] * f.arm[2]);
}

// The same as a body vector [v; w_body], the model's generalized velocities' form.
inline Vec6 body_response(const ContactPoint& c, const Frame& f, const Vec3& dp) noexcept {
  Vec6 x;
  x << linear_response(c, dp), angular_response(c, f, dp);
  return x;
}

// The point's velocity along (normal, tangent1, tangent2) for its body's
// velocities u = [v; w_body].
inline Vec3 point_velocity_of(const ContactPoint& c, const Frame& f, const Vec6& u) noexcept {
  Vec3 r(c.normal.dot(u.head<3>()), c.tangent1.dot(u.head<3>()), c.tangent2.dot(u.head<3>()));
  for (int k = 0; k < 3; ++k) r[k] += f.arm[k].dot(u.tail<3>());
  return r;
}

// The body's displacement from a position impulse dP at the point.
inline void displace(const ContactPoint& c, const ContactBody& b, const Frame& f, const Vec3& dp) noexcept {
  *b.r += linear_response(c, dp);
  if (b.p) *b.p = quaternion_product(*b.p, cayley_increment(angular_response(c, f, dp)));
}

// The contact's 3x3 block of the Delassus matrix J M^-1 J^T.
inline Mat3 delassus_block(const ContactPoint& c, const Frame& f) noexcept {
  Mat3 d = c.inverse_mass * Mat3::Identity();
  for (int k = 0; k < 3; ++k) {
    const Vec3 m = c.inverse_inertia * f.arm[k];
    for (int l = 0; l < 3; ++l) d(l, k) += f.arm[l].dot(m);
  }
  return d;
}

}  // namespace contact_detail

}  // namespace mbrt
