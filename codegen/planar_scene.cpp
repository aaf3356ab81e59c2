#include "planar_scene.hpp"

namespace mbrt::codegen {

namespace {

bool in_plane(const Eigen::Vector3d& v) { return v.z() == 0.0; }
bool along_z(const Eigen::Vector3d& v) { return v.x() == 0.0 && v.y() == 0.0; }

// The motion stays in the x-y plane and its out-of-plane multipliers stay
// zero when every body starts in it turned about z alone, moving in it, and
// no inertia product couples z with x or y (such a product would need an
// out-of-plane reaction that the planar step does not compute).
std::string body_refusal(const Body& b) {
  if (!in_plane(b.velocity)) return "body " + b.name + " moves out of the x-y plane";
  if (b.particle) return "";
  if (b.orientation[1] != 0.0 || b.orientation[2] != 0.0) return "body " + b.name + " is not turned about z alone";
  if (!along_z(b.angular_velocity)) return "body " + b.name + " turns about an axis other than z";
  if (b.inertia(0, 2) != 0.0 || b.inertia(1, 2) != 0.0) {
    return "the inertia of body " + b.name + " couples z with x or y";
  }
  return "";
}

// A joint or driver point off its body's plane z = z_COM would take
// out-of-plane reactions (and let a spherical joint tilt the body).
bool points_in_planes(const ConstraintBlock& block) {
  return (block.body1 == kGround || in_plane(block.frame.s1)) && (block.body2 == kGround || in_plane(block.frame.s2));
}

// The planar prismatic kernel keeps the rows of the spatial prismatic block
// (joints.hpp: a1.b2, a1.c2, b1.d, c1.d, b1.c2) that do not involve the
// normal of the plane. For an axis in the plane, the triad of
// complete_triad (analysis.cpp) has b or c along +-z: b = a x z for an
// oblique axis, a x y or a x x for one along x or y. Any other triad is
// refused rather than turned, which would change the spatial step.
std::string planar_prismatic(const Joint& j, ConstraintBlock& block) {
  if (!in_plane(j.axis)) return "the axis of joint " + j.name + " is not in the x-y plane";
  const JointFrame& f = block.frame;
  if (along_z(f.c1) && along_z(f.c2) && in_plane(f.b1) && in_plane(f.b2)) {
    block.kernel = "planar_prismatic<mbrt::InPlane::b>";
    block.spatial_rows = {0, 2};
  } else if (along_z(f.b1) && along_z(f.b2) && in_plane(f.c1) && in_plane(f.c2)) {
    block.kernel = "planar_prismatic<mbrt::InPlane::c>";
    block.spatial_rows = {1, 3};
  } else {
    return "the frame of joint " + j.name + " is tilted out of the x-y plane";
  }
  return "";
}

// Planar kernel and in-plane rows of a joint, or a refusal.
std::string planar_joint(const Joint& j, ConstraintBlock& block) {
  if (!points_in_planes(block)) return "joint " + j.name + " is off the plane of a body's centre of mass";
  switch (j.type) {
    case JointType::revolute:
      if (!along_z(j.axis)) return "the axis of joint " + j.name + " is not z";
      [[fallthrough]];
    case JointType::spherical:
      block.kernel = "planar_revolute";
      block.spatial_rows = {0, 1};
      return "";
    case JointType::distance:
      if (!in_plane(j.point2 - j.point1)) {
        return "the points of distance joint " + j.name + " are not in one x-y plane";
      }
      block.kernel = "planar_distance";
      block.spatial_rows = {0};
      return "";
    case JointType::prismatic: return planar_prismatic(j, block);
    default: return "joint " + j.name + " is a " + joint_type_name(j.type) + " joint";
  }
}

// Planar kernel of a driver, or a refusal. A joint_angle or joint_distance
// driver measures its joint, which planar_joint has taken (a revolute joint
// about z, a prismatic one along the plane), in that joint's frame.
std::string planar_driver(const Driver& d, ConstraintBlock& block) {
  if (!points_in_planes(block)) return "driver " + d.name + " is off the plane of a body's centre of mass";
  if (d.type == DriverType::distance && !in_plane(d.point2 - d.point1)) {
    return "the points of distance driver " + d.name + " are not in one x-y plane";
  }
  block.kernel = "planar_" + block.kernel;
  block.spatial_rows = {0};
  return "";
}

// Loads in the plane, acting in their bodies' planes of motion.
std::string force_refusal(const Force& f, const ForcePlan& p) {
  switch (f.type) {
    case ForceType::spring_damper:
      if (!in_plane(f.point2 - f.point1) || (f.body1 != kGround && !in_plane(p.spring.s1)) ||
          (f.body2 != kGround && !in_plane(p.spring.s2))) {
        return "a spring_damper is off the plane of a body's centre of mass";
      }
      return "";
    case ForceType::torque: return along_z(f.axis) ? "" : "a torque is not about z";
    case ForceType::force: return in_plane(f.vector) && in_plane(p.point) ? "" : "a force is out of its body's plane";
  }
  return "";
}

std::string refusal(const Model& model, const Analysis& a, PlanarPlan& plan) {
  if (model.solver.scheme != "staggered-pcst") return "not for scheme " + model.solver.scheme;
  for (const ForcePlan& p : a.forces) {
    if (std::string why = force_refusal(model.forces[static_cast<size_t>(p.model_index)], p); !why.empty()) return why;
  }
  for (size_t i = 0; i < model.inputs.size(); ++i) {
    const Input& in = model.inputs[i];
    // A joint_force acts along its joint's axis, a torque about it.
    if (in.type == InputType::joint_force) {
      if (!in_plane(a.inputs[i].axis1)) return "input " + in.name + " is not a force in the x-y plane";
    } else if (!along_z(a.inputs[i].axis1)) {
      return "input " + in.name + " is not a torque about z";
    }
  }
  if (model.gravity && !in_plane(*model.gravity)) return "gravity is not in the x-y plane";
  for (const Body& b : model.bodies) {
    if (std::string why = body_refusal(b); !why.empty()) return why;
  }
  const size_t joints = model.joints.size();
  for (size_t i = 0; i < a.constraints.size(); ++i) {
    ConstraintBlock block = a.constraints[i];
    const std::string why =
        i < joints ? planar_joint(model.joints[i], block) : planar_driver(model.drivers[i - joints], block);
    if (!why.empty()) return why;
    block.rows = static_cast<int>(block.spatial_rows.size());
    block.first_row = plan.constraint_rows;
    block.holonomic_rows = block.rows;
    plan.constraint_rows += block.rows;
    plan.constraints.push_back(block);
  }
  return "";
}

}  // namespace

PlanarPlan plan_planar(const Model& model, const Analysis& a) {
  PlanarPlan plan;
  if (!a.specialize.planar) return plan;
  plan.refusal = refusal(model, a, plan);
  plan.applies = plan.refusal.empty();
  if (!plan.applies) {
    plan.constraints.clear();
    plan.constraint_rows = 0;
  }
  return plan;
}

}  // namespace mbrt::codegen
