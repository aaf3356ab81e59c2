#include "planar_scene.hpp"

#include <algorithm>
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

// A joint or driver point off its body's plane through the centre of mass
// would take out-of-plane reactions (and let a spherical joint tilt the body).
bool points_in_planes(const Plane& plane, const ConstraintBlock& block) {
  return (block.body1 == kGround || plane.contains(block.frame.s1)) &&
         (block.body2 == kGround || plane.contains(block.frame.s2));
}

// The planar prismatic kernel keeps the rows of the spatial prismatic block
// (joints.hpp: a1.b2, a1.c2, b1.d, c1.d, b1.c2) that do not involve the
// normal of the plane. For an axis in a coordinate plane, the triad of
// complete_triad (analysis.cpp) has b or c along the normal: b = a x z for
// an axis oblique to x and y, a x y or a x x for one along x or y. Any other
// triad is refused rather than turned, which would change the spatial step.
std::string planar_prismatic(const Plane& plane, const Joint& j, ConstraintBlock& block) {
  if (!plane.contains(j.axis)) return "the axis of joint " + j.name + " is not in the " + plane.name() + " plane";
  const JointFrame& f = block.frame;
  const auto normal_and_in_plane = [&](const Eigen::Vector3d& n1, const Eigen::Vector3d& n2, const Eigen::Vector3d& e1,
                                       const Eigen::Vector3d& e2) {
    return plane.along_normal(n1) && plane.along_normal(n2) && plane.contains(e1) && plane.contains(e2);
  };
  if (normal_and_in_plane(f.c1, f.c2, f.b1, f.b2)) {
    block.kernel = "planar_prismatic<mbrt::InPlane::b>";
    block.spatial_rows = {0, 2};
  } else if (normal_and_in_plane(f.b1, f.b2, f.c1, f.c2)) {
    block.kernel = "planar_prismatic<mbrt::InPlane::c>";
    block.spatial_rows = {1, 3};
  } else {
    return "the frame of joint " + j.name + " is tilted out of the " + plane.name() + " plane";
  }
  return "";
}

// Planar kernel and in-plane rows of a joint, each with its row in the
// spatial block, or a refusal.
std::string planar_joint(const Plane& plane, const Joint& j, ConstraintBlock& block) {
  if (!points_in_planes(plane, block)) return "joint " + j.name + " is off the plane of a body's centre of mass";
  switch (j.type) {
    case JointType::revolute:
      if (!plane.along_normal(j.axis)) return "the axis of joint " + j.name + " is not along " + plane.axis_name();
      [[fallthrough]];
    case JointType::spherical:
      block.kernel = "planar_revolute";
      block.spatial_rows = {plane.i(), plane.j()};  // of the point coincidence's x, y, z rows
      return "";
    case JointType::distance:
      if (!plane.contains(j.point2 - j.point1)) {
        return "the points of distance joint " + j.name + " are not in one " + plane.name() + " plane";
      }
      block.kernel = "planar_distance";
      block.spatial_rows = {0};
      return "";
    case JointType::prismatic: return planar_prismatic(plane, j, block);
    case JointType::universal:
    case JointType::cylindrical:
    case JointType::fixed:
    case JointType::screw:
    case JointType::planar:
    case JointType::rolling_disk:
    case JointType::rolling_ball:
    case JointType::knife_edge:
    case JointType::velocity_toward: break;
  }
  return "joint " + j.name + " is a " + type_row(j.type).name + " joint";
}

// Planar kernel of a driver, or a refusal. A joint_angle or joint_distance
// driver measures its joint, which planar_joint has taken (a revolute joint
// about the normal, a prismatic one along the plane), in that joint's frame.
std::string planar_driver(const Plane& plane, const Driver& d, ConstraintBlock& block) {
  if (!points_in_planes(plane, block)) return "driver " + d.name + " is off the plane of a body's centre of mass";
  if (d.type == DriverType::distance && !plane.contains(d.point2 - d.point1)) {
    return "the points of distance driver " + d.name + " are not in one " + plane.name() + " plane";
  }
  block.kernel = std::string("planar_") + type_row(d.type).kernel;
  block.spatial_rows = {0};
  return "";
}

// Loads in the plane, acting in their bodies' planes of motion.
std::string force_refusal(const Plane& plane, const Force& f, const ForcePlan& p) {
  switch (f.type) {
    case ForceType::spring_damper:
      if (!plane.contains(f.point2 - f.point1) || (f.body1 != kGround && !plane.contains(p.spring.s1)) ||
          (f.body2 != kGround && !plane.contains(p.spring.s2))) {
        return "a spring_damper is off the plane of a body's centre of mass";
      }
      return "";
    case ForceType::torque: return plane.along_normal(f.axis) ? "" : "a torque is not about " + plane.axis_name();
    case ForceType::force:
      return plane.contains(f.vector) && plane.contains(p.point) ? "" : "a force is out of its body's " + plane.name() + " plane";
    case ForceType::joint_spring: return "";  // in the plane when its joint is (planar_joint)
  }
  return "";
}

// Why the scene does not move in the plane, or "" with plan's blocks filled in.
std::string refusal(const Plane& plane, const Model& model, const Analysis& a, PlanarPlan& plan) {
  for (const ForcePlan& p : a.forces) {
    if (std::string why = force_refusal(plane, model.forces[static_cast<size_t>(p.model_index)], p); !why.empty()) return why;
  }
  for (size_t i = 0; i < model.inputs.size(); ++i) {
    const Input& in = model.inputs[i];
    // A joint_force acts along its joint's axis, a torque about it.
    if (in.type == InputType::joint_force) {
      if (!plane.contains(a.inputs[i].axis1)) return "input " + in.name + " is not a force in the " + plane.name() + " plane";
    } else if (!plane.along_normal(a.inputs[i].axis1)) {
      return "input " + in.name + " is not a torque about " + plane.axis_name();
    }
  }
  if (model.gravity && !plane.contains(*model.gravity)) return "gravity is not in the " + plane.name() + " plane";
  for (const Body& b : model.bodies) {
    if (std::string why = body_refusal(plane, b); !why.empty()) return why;
  }
  const size_t joints = model.joints.size();
  for (size_t i = 0; i < a.constraints.size(); ++i) {
    ConstraintBlock block = a.constraints[i];
    const std::string why = i < joints ? planar_joint(plane, model.joints[i], block)
                                       : planar_driver(plane, model.drivers[i - joints], block);
    if (!why.empty()) return why;
    block.rows = static_cast<int>(block.spatial_rows.size());
    block.first_row = plan.constraint_rows;
    block.holonomic_rows = block.rows;
    plan.constraint_rows += block.rows;
    plan.constraints.push_back(block);
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
  if (!a.contacts.empty()) {
    plan.refusal = "the model has contacts (docs/contact.md)";
    return plan;
  }
  if (!a.beams.empty() || !a.modal.empty()) {
    plan.refusal = "the model has flexible bodies (docs/flexible.md)";
    return plan;
  }
  for (const Joint& j : model.joints) {
    if (j.friction.any()) {  // the planar step has no impulse path
      plan.refusal = "the model has joint friction (docs/friction.md)";
      return plan;
    }
  }
  if (a.tunable) {  // the planar kernels fold the model's values
    plan.refusal = "the model has tunable keys (docs/parameters.md)";
    return plan;
  }
  switch (model.solver.scheme) {
    case mbrt::Scheme::staggered_pcst:
    case mbrt::Scheme::baumgarte:
    case mbrt::Scheme::blajer: break;
    case mbrt::Scheme::staggered_nps:
    case mbrt::Scheme::staggered_tree:
    case mbrt::Scheme::midpoint_tree:
    case mbrt::Scheme::rk4_tree:
    case mbrt::Scheme::rk8_tree:
    case mbrt::Scheme::rk4_projected:
    case mbrt::Scheme::staggered4:
    case mbrt::Scheme::ali3p:
      plan.refusal = "not for scheme " + std::string(mbrt::scheme_name(model.solver.scheme));
      return plan;
  }
  std::vector<std::string> reasons;
  for (const int normal : {2, 1, 0}) {  // x-y first: the plane of most planar benchmarks
    plan = PlanarPlan{};
    reasons.push_back(refusal(Plane{normal}, model, a, plan));
    if (reasons.back().empty()) {
      plan.applies = true;
      // Turning about the normal, a principal axis, no body has a gyroscopic
      // torque: without dampers (and Baumgarte's velocity term) one implicit pass.
      const bool damped = std::any_of(model.forces.begin(), model.forces.end(), [](const Force& f) {
        return (f.type == ForceType::spring_damper || f.type == ForceType::joint_spring) && f.damping != 0.0;
      });
      const bool baumgarte = model.solver.scheme == mbrt::Scheme::baumgarte && plan.constraint_rows > 0;
      plan.stages = a.specialize.single_stage && !damped && !baumgarte ? 1 : 2;
      return plan;
    }
  }
  plan = PlanarPlan{};
  plan.refusal = joined(reasons);
  return plan;
}

}  // namespace mbrt::codegen
