#include "planar_scene.hpp"

#include <array>

namespace mbrt::codegen {

std::string Plane::name() const { return std::array{"y-z", "x-z", "x-y"}[static_cast<size_t>(normal)]; }
std::string Plane::axis_name() const { return std::array{"x", "y", "z"}[static_cast<size_t>(normal)]; }

namespace {

// The motion stays in the plane and its out-of-plane multipliers stay zero
// when every body starts in it turned about the normal alone, moving in it,
// and no inertia product couples the normal with the plane (such a product
// would need an out-of-plane reaction that the planar step does not compute).
std::string body_refusal(const Plane& plane, const Body& b) {
  if (!plane.contains(b.velocity)) return "body " + b.name + " moves out of the " + plane.name() + " plane";
  if (b.particle) return "";
  if (b.orientation[1 + plane.i()] != 0.0 || b.orientation[1 + plane.j()] != 0.0) {
    return "body " + b.name + " is not turned about " + plane.axis_name() + " alone";
  }
  if (!plane.along_normal(b.angular_velocity)) return "body " + b.name + " turns about an axis other than " + plane.axis_name();
  if (b.inertia(plane.i(), plane.normal) != 0.0 || b.inertia(plane.j(), plane.normal) != 0.0) {
    return "the inertia of body " + b.name + " couples " + plane.axis_name() + " with the " + plane.name() + " plane";
  }
  return "";
}

// Planar kernel and in-plane rows of a joint, each with its row in the
// spatial block, or a refusal. A joint point off its body's plane through
// the centre of mass would take out-of-plane reactions (and let a spherical
// joint tilt the body).
std::string planar_joint(const Plane& plane, const Joint& j, ConstraintBlock& block, std::vector<int>& spatial_rows) {
  if ((j.body1 != kGround && !plane.contains(block.frame.s1)) || (j.body2 != kGround && !plane.contains(block.frame.s2))) {
    return "joint " + j.name + " is off the plane of a body's centre of mass";
  }
  switch (j.type) {
    case JointType::revolute:
      if (!plane.along_normal(j.axis)) return "the axis of joint " + j.name + " is not along " + plane.axis_name();
      [[fallthrough]];
    case JointType::spherical:
      block.kernel = "planar_revolute";
      block.rows = 2;
      spatial_rows = {plane.i(), plane.j()};  // of the point coincidence's x, y, z rows
      return "";
    case JointType::distance:
      if (j.point1[plane.normal] != j.point2[plane.normal]) {
        return "the points of distance joint " + j.name + " are not in one " + plane.name() + " plane";
      }
      block.kernel = "planar_distance";
      block.rows = 1;
      spatial_rows = {0};
      return "";
    default: return "joint " + j.name + " is a " + joint_type_name(j.type) + " joint";
  }
}

// Loads in the plane, acting in their bodies' planes of motion.
std::string force_refusal(const Plane& plane, const Force& f, const ForcePlan& p) {
  switch (f.type) {
    case ForceType::spring_damper:
      if (f.point1[plane.normal] != f.point2[plane.normal] || (f.body1 != kGround && !plane.contains(p.spring.s1)) ||
          (f.body2 != kGround && !plane.contains(p.spring.s2))) {
        return "a spring_damper is off the plane of a body's centre of mass";
      }
      return "";
    case ForceType::torque: return plane.along_normal(f.axis) ? "" : "a torque is not about " + plane.axis_name();
    case ForceType::force:
      return plane.contains(f.vector) && plane.contains(p.point) ? "" : "a force is out of its body's " + plane.name() + " plane";
  }
  return "";
}

// Why the scene does not move in the plane, or "" with plan's blocks filled in.
std::string refusal(const Plane& plane, const Model& model, const Analysis& a, PlanarPlan& plan) {
  if (!model.drivers.empty()) return "the scene has drivers";
  for (const ForcePlan& p : a.forces) {
    if (std::string why = force_refusal(plane, model.forces[static_cast<size_t>(p.model_index)], p); !why.empty()) return why;
  }
  for (size_t i = 0; i < model.inputs.size(); ++i) {
    const Input& in = model.inputs[i];
    if (in.type == InputType::joint_force) return "input " + in.name + " is a joint_force";
    if (!plane.along_normal(a.inputs[i].axis1)) return "input " + in.name + " is not a torque about " + plane.axis_name();
  }
  if (model.gravity && !plane.contains(*model.gravity)) return "gravity is not in the " + plane.name() + " plane";
  for (const Body& b : model.bodies) {
    if (std::string why = body_refusal(plane, b); !why.empty()) return why;
  }
  for (size_t i = 0; i < model.joints.size(); ++i) {
    ConstraintBlock block = a.constraints[i];
    std::vector<int> rows;
    if (std::string why = planar_joint(plane, model.joints[i], block, rows); !why.empty()) return why;
    block.first_row = plan.constraint_rows;
    block.holonomic_rows = block.rows;
    plan.constraint_rows += block.rows;
    plan.constraints.push_back(block);
    plan.spatial_rows.push_back(rows);
  }
  plan.normal = plane.normal;
  return "";
}

// Reasons for each plane, each said once.
std::string joined(const std::vector<std::string>& reasons) {
  std::string out;
  for (const std::string& r : reasons) {
    if (out.find(r) == std::string::npos) out += (out.empty() ? "" : "; ") + r;
  }
  return out;
}

}  // namespace

PlanarPlan plan_planar(const Model& model, const Analysis& a) {
  PlanarPlan plan;
  if (!a.specialize.planar) return plan;
  const std::string& scheme = model.solver.scheme;
  if (scheme != "staggered-pcst" && scheme != "baumgarte" && scheme != "blajer") {
    plan.refusal = "not for scheme " + model.solver.scheme;
    return plan;
  }
  std::vector<std::string> reasons;
  for (const int normal : {2, 1, 0}) {  // x-y first: the plane of most planar benchmarks
    plan = PlanarPlan{};
    reasons.push_back(refusal(Plane{normal}, model, a, plan));
    if (reasons.back().empty()) {
      plan.applies = true;
      return plan;
    }
  }
  plan = PlanarPlan{};
  plan.refusal = joined(reasons);
  return plan;
}

}  // namespace mbrt::codegen
