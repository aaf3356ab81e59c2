// Applied-force kernels. A Wrench holds the force on a body in world axes and
// the torque about its COM in body axes, matching u = [v; w_body].
#pragma once

#include <cmath>

#include "mbrt/joint_coordinates.hpp"
#include "mbrt/joints.hpp"

namespace mbrt {

struct Wrench {
  Vec3 f = Vec3::Zero();
  Vec3 tau = Vec3::Zero();
};

// Force f (world) applied at body-frame point s.
inline void add_point_force(Wrench& w, const BodyPose& pose, const Vec3& s, const Vec3& f) noexcept {
  w.f += f;
  w.tau += s.cross(pose.R.transpose() * f);
}

// Linear spring-damper between point s1 of body 1 and s2 of body 2.
struct SpringDamper {
  Vec3 s1, s2;
  double stiffness, damping, rest_length;
};

struct SpringDamperForce {
  Vec3 x1, x2;     // attachment points, world
  Vec3 f2;         // force on body 2 at x2 (body 1 gets -f2 at x1), world
  double energy;   // stored elastic energy
};

inline SpringDamperForce spring_damper(const SpringDamper& e, const BodyMotion& m1, const BodyMotion& m2) noexcept {
  const CarriedVector p1 = carried_point(m1.pose, m1.vel, e.s1);
  const CarriedVector p2 = carried_point(m2.pose, m2.vel, e.s2);
  const Vec3 d = p2.x - p1.x;
  const double l = d.norm();
  const double stretch = l - e.rest_length;
  SpringDamperForce out{p1.x, p2.x, Vec3::Zero(), 0.5 * e.stiffness * stretch * stretch};
  if (l > 1e-12) {  // coincident points have no line of action
    const Vec3 n = d / l;
    const double tension = e.stiffness * stretch + e.damping * n.dot(p2.x_dot - p1.x_dot);
    out.f2 = -tension * n;
  }
  return out;
}

// Pure torque `value` about an axis fixed in body 1 (axis1, body-1 axes),
// acting on body 2 with the reaction on body 1.
struct AxialTorque {
  Vec3 axis1;
  double value;
};

inline Vec3 axial_torque_world(const AxialTorque& t, const BodyPose& pose1) noexcept {
  return t.value * (pose1.R * t.axis1);
}

// Spring-damper across a revolute or prismatic joint, on its coordinate q
// (angle or slide from t = 0, joint_coordinates.hpp): the torque about, or
// the force along, the joint axis on body 2 (body 1 gets the opposite).
struct JointSpring {
  double stiffness;  // N m/rad or N/m
  double damping;    // N m s/rad or N s/m
  double rest;       // rad or m
};

struct JointSpringLoad {
  double value;   // N m or N
  double energy;  // stored elastic energy
};

inline JointSpringLoad joint_spring(const JointSpring& e, const JointCoordinate& q) noexcept {
  const double stretch = q.position - e.rest;
  return {-e.stiffness * stretch - e.damping * q.velocity, 0.5 * e.stiffness * stretch * stretch};
}

// Gyroscopic torque -w x (J w), body axes.
template <class Inertia>
inline Vec3 gyroscopic_torque(const Inertia& b, const Vec3& w) noexcept {
  return -w.cross(inertia_times(b, w));
}

}  // namespace mbrt
