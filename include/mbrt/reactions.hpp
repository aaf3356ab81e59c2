// Joint reactions from constraint multipliers: the force and torque a joint
// (or driver) transmits to its body2, at body2's joint point.
#pragma once

#include "mbrt/joints.hpp"
#include "mbrt/model_api.hpp"

namespace mbrt {

// w: the constraint's generalized force -J^T lambda on `body` ([force,
// world; torque about the COM, body axes]); point: body2's joint point
// (world). `body` is body2 (sign +1), or body1 when body2 is the ground
// (sign -1: the ground receives the opposite of what body1 does).
inline JointReaction joint_reaction(const Vec6& w, const BodyPose& body, const Vec3& point, double sign,
                                    const BodyPose& pose1, const JointFrame& frame) noexcept {
  const Vec3 f = w.head<3>();
  const Vec3 torque_com = body.R * w.tail<3>();
  JointReaction r;
  r.force = sign * f;
  r.torque = sign * (torque_com - (point - body.r).cross(f));
  Mat3 axes;  // the joint frame: body 1's a1, b1, c1 in world
  axes << pose1.R * frame.a1, pose1.R * frame.b1, pose1.R * frame.c1;
  r.force_joint = axes.transpose() * r.force;
  r.torque_joint = axes.transpose() * r.torque;
  return r;
}

}  // namespace mbrt
