#include "constraint_evaluation.hpp"

#include <mbrt/body_state.hpp>

namespace mbrt::codegen {

namespace {

struct Motion {
  mbrt::BodyPose pose;
  mbrt::BodyVelocity vel;
};

Motion motion_of(const Model& model, int index) {
  if (index == kGround) return {mbrt::ground_pose(), mbrt::ground_velocity()};
  const Body& b = model.bodies[static_cast<size_t>(index)];
  if (b.particle) return {{b.position, Eigen::Matrix3d::Identity()}, {b.velocity, Eigen::Vector3d::Zero()}};
  return {{b.position, mbrt::rotation_matrix(b.orientation)}, {b.velocity, b.angular_velocity}};
}

template <int N>
void stack(const mbrt::ConstraintRows<N>& rows, const Joint& joint, int first_row, StackedConstraints& out) {
  out.phi.segment<N>(first_row) = rows.phi;
  if (joint.body1 != kGround) out.B.block<N, 6>(first_row, 6 * joint.body1) += rows.J1;
  if (joint.body2 != kGround) out.B.block<N, 6>(first_row, 6 * joint.body2) += rows.J2;
}

}  // namespace

StackedConstraints evaluate_constraints(const Model& model, const std::vector<JointPlan>& joints) {
  int rows = 0;
  for (const JointPlan& j : joints) rows += j.rows;
  StackedConstraints out;
  out.phi = Eigen::VectorXd::Zero(rows);
  out.B = Eigen::MatrixXd::Zero(rows, 6 * static_cast<int>(model.bodies.size()));
  for (const JointPlan& plan : joints) {
    const Joint& joint = model.joints[static_cast<size_t>(plan.model_index)];
    const Motion a = motion_of(model, joint.body1);
    const Motion b = motion_of(model, joint.body2);
    const mbrt::BodyMotion m1{a.pose, a.vel};
    const mbrt::BodyMotion m2{b.pose, b.vel};
    switch (joint.type) {
      case JointType::spherical: stack(mbrt::spherical(plan.frame, m1, m2), joint, plan.first_row, out); break;
      case JointType::revolute: stack(mbrt::revolute(plan.frame, m1, m2), joint, plan.first_row, out); break;
      case JointType::universal: stack(mbrt::universal(plan.frame, m1, m2), joint, plan.first_row, out); break;
      case JointType::cylindrical: stack(mbrt::cylindrical(plan.frame, m1, m2), joint, plan.first_row, out); break;
      case JointType::prismatic: stack(mbrt::prismatic(plan.frame, m1, m2), joint, plan.first_row, out); break;
      case JointType::fixed: stack(mbrt::fixed(plan.frame, m1, m2), joint, plan.first_row, out); break;
      case JointType::distance: stack(mbrt::distance(plan.frame, m1, m2), joint, plan.first_row, out); break;
    }
  }
  Eigen::VectorXd u(6 * model.bodies.size());
  for (size_t i = 0; i < model.bodies.size(); ++i) {
    const Motion m = motion_of(model, static_cast<int>(i));
    u.segment<3>(6 * static_cast<int>(i)) = m.vel.v;
    u.segment<3>(6 * static_cast<int>(i) + 3) = m.vel.w;
  }
  out.phi_dot = out.B * u;
  return out;
}

Eigen::MatrixXd inverse_mass_matrix(const Model& model) {
  const int n = static_cast<int>(model.bodies.size());
  Eigen::MatrixXd m_inv = Eigen::MatrixXd::Zero(6 * n, 6 * n);
  for (int i = 0; i < n; ++i) {
    const Body& b = model.bodies[static_cast<size_t>(i)];
    m_inv.block<3, 3>(6 * i, 6 * i) = Eigen::Matrix3d::Identity() / b.mass;
    if (!b.particle) m_inv.block<3, 3>(6 * i + 3, 6 * i + 3) = b.inertia.inverse();
  }
  return m_inv;
}

}  // namespace mbrt::codegen
