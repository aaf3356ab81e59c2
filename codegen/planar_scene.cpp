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

// Planar kernel and in-plane rows of a joint, or a refusal. A joint point
// off its body's plane z = z_COM would take out-of-plane reactions (and let
// a spherical joint tilt the body).
std::string planar_joint(const Model& model, const Joint& j, ConstraintBlock& block) {
  if ((j.body1 != kGround && block.frame.s1.z() != 0.0) || (j.body2 != kGround && block.frame.s2.z() != 0.0)) {
    return "joint " + j.name + " is off the plane of a body's centre of mass";
  }
  switch (j.type) {
    case JointType::revolute:
      if (!along_z(j.axis)) return "the axis of joint " + j.name + " is not z";
      [[fallthrough]];
    case JointType::spherical:
      block.kernel = "planar_revolute";
      block.rows = 2;
      return "";
    case JointType::distance:
      if (j.point1.z() != j.point2.z()) {
        return "the points of distance joint " + j.name + " are not in one x-y plane";
      }
      block.kernel = "planar_distance";
      block.rows = 1;
      return "";
    default: return "joint " + j.name + " is a " + joint_type_name(j.type) + " joint";
  }
}

// Loads in the plane, acting in their bodies' planes of motion.
std::string force_refusal(const Force& f, const ForcePlan& p) {
  switch (f.type) {
    case ForceType::spring_damper:
      if (f.point1.z() != f.point2.z() || (f.body1 != kGround && p.spring.s1.z() != 0.0) ||
          (f.body2 != kGround && p.spring.s2.z() != 0.0)) {
        return "a spring_damper is off the plane of a body's centre of mass";
      }
      return "";
    case ForceType::torque: return along_z(f.axis) ? "" : "a torque is not about z";
    case ForceType::force: return in_plane(f.vector) && p.point.z() == 0.0 ? "" : "a force is out of its body's plane";
  }
  return "";
}

std::string refusal(const Model& model, const Analysis& a, PlanarPlan& plan) {
  if (model.solver.scheme != "staggered-pcst") return "not for scheme " + model.solver.scheme;
  if (!model.drivers.empty()) return "the scene has drivers";
  for (const ForcePlan& p : a.forces) {
    if (std::string why = force_refusal(model.forces[static_cast<size_t>(p.model_index)], p); !why.empty()) return why;
  }
  for (size_t i = 0; i < model.inputs.size(); ++i) {
    const Input& in = model.inputs[i];
    if (in.type == InputType::joint_force) return "input " + in.name + " is a joint_force";
    if (!along_z(a.inputs[i].axis1)) return "input " + in.name + " is not a torque about z";
  }
  if (model.gravity && !in_plane(*model.gravity)) return "gravity is not in the x-y plane";
  for (const Body& b : model.bodies) {
    if (std::string why = body_refusal(b); !why.empty()) return why;
  }
  for (size_t i = 0; i < model.joints.size(); ++i) {
    ConstraintBlock block = a.constraints[i];
    if (std::string why = planar_joint(model, model.joints[i], block); !why.empty()) return why;
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
