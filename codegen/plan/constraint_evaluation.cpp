#include "constraint_evaluation.hpp"

#include <mbrt/body_state.hpp>
#include <mbrt/nonholonomic.hpp>

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

// A kernel's rows in their place; `type` names the table row whose row count
// must be the kernel's.
template <auto type, int N>
void stack(const mbrt::ConstraintRows<N>& rows, const ConstraintBlock& block, StackedConstraints& out) {
  static_assert(N == type_row(type).rows, "the type's table row gives another row count than its kernel");
  out.phi.segment<N>(block.first_row) = rows.phi;
  out.phi_t.segment<N>(block.first_row) = rows.phi_t;
  if (block.body1 != kGround) out.B.block<N, 6>(block.first_row, 6 * block.body1) += rows.J1;
  if (block.body2 != kGround) out.B.block<N, 6>(block.first_row, 6 * block.body2) += rows.J2;
}

// The runtime kernels the generated code calls (the table rows' kernel).
void evaluate_joint(const ConstraintBlock& b, const mbrt::BodyMotion& m1, const mbrt::BodyMotion& m2,
                    StackedConstraints& out) {
  const mbrt::JointFrame& f = b.frame;
  switch (b.joint_type) {
    case JointType::spherical: return stack<JointType::spherical>(mbrt::spherical(f, m1, m2), b, out);
    case JointType::revolute: return stack<JointType::revolute>(mbrt::revolute(f, m1, m2), b, out);
    case JointType::universal: return stack<JointType::universal>(mbrt::universal(f, m1, m2), b, out);
    case JointType::cylindrical: return stack<JointType::cylindrical>(mbrt::cylindrical(f, m1, m2), b, out);
    case JointType::prismatic: return stack<JointType::prismatic>(mbrt::prismatic(f, m1, m2), b, out);
    case JointType::fixed: return stack<JointType::fixed>(mbrt::fixed(f, m1, m2), b, out);
    case JointType::distance: return stack<JointType::distance>(mbrt::distance(f, m1, m2), b, out);
    case JointType::screw: return stack<JointType::screw>(mbrt::screw(f, m1, m2), b, out);
    case JointType::planar: return stack<JointType::planar>(mbrt::planar(f, m1, m2), b, out);
    case JointType::rolling_disk: return stack<JointType::rolling_disk>(mbrt::rolling_disk(f, m1, m2), b, out);
    case JointType::rolling_ball: return stack<JointType::rolling_ball>(mbrt::rolling_ball(f, m1, m2), b, out);
    case JointType::knife_edge: return stack<JointType::knife_edge>(mbrt::knife_edge(f, m1, m2), b, out);
    case JointType::velocity_toward:
      return stack<JointType::velocity_toward>(mbrt::velocity_toward(f, m1, m2), b, out);
  }
}

void evaluate_driver(const ConstraintBlock& b, const mbrt::BodyMotion& m1, const mbrt::BodyMotion& m2, double t,
                     StackedConstraints& out) {
  const mbrt::JointFrame& f = b.frame;
  const mbrt::TimeValue target = evaluate(*b.function, t);
  switch (b.driver_type) {
    case DriverType::joint_angle:
      return stack<DriverType::joint_angle>(mbrt::joint_angle_driver(f, m1, m2, target), b, out);
    case DriverType::joint_distance:
      return stack<DriverType::joint_distance>(mbrt::joint_distance_driver(f, m1, m2, target), b, out);
    case DriverType::distance: return stack<DriverType::distance>(mbrt::distance_driver(f, m1, m2, target), b, out);
  }
}

}  // namespace

StackedConstraints evaluate_constraints(const Model& model, const std::vector<ConstraintBlock>& blocks, double t) {
  int rows = 0;
  for (const ConstraintBlock& b : blocks) rows += b.rows;
  StackedConstraints out;
  out.phi = Eigen::VectorXd::Zero(rows);
  out.phi_t = Eigen::VectorXd::Zero(rows);
  out.B = Eigen::MatrixXd::Zero(rows, 6 * static_cast<int>(model.bodies.size()));
  for (const ConstraintBlock& block : blocks) {
    const Motion a = motion_of(model, block.body1);
    const Motion b = motion_of(model, block.body2);
    const mbrt::BodyMotion m1{a.pose, a.vel};
    const mbrt::BodyMotion m2{b.pose, b.vel};
    switch (block.source) {
      case ConstraintSource::joint: evaluate_joint(block, m1, m2, out); break;
      case ConstraintSource::driver: evaluate_driver(block, m1, m2, t, out); break;
    }
  }
  Eigen::VectorXd u(6 * model.bodies.size());
  for (size_t i = 0; i < model.bodies.size(); ++i) {
    const Motion m = motion_of(model, static_cast<int>(i));
    u.segment<3>(6 * static_cast<int>(i)) = m.vel.v;
    u.segment<3>(6 * static_cast<int>(i) + 3) = m.vel.w;
  }
  out.phi_dot = out.B * u + out.phi_t;
  return out;
}

Eigen::SparseMatrix<double> inverse_mass_matrix(const Model& model) {
  std::vector<Eigen::Triplet<double>> entries;
  for (size_t i = 0; i < model.bodies.size(); ++i) {
    const Body& b = model.bodies[i];
    const int k = 6 * static_cast<int>(i);
    for (int d = 0; d < 3; ++d) entries.emplace_back(k + d, k + d, 1.0 / b.mass);
    if (b.particle) continue;
    const Eigen::Matrix3d j_inv = b.inertia.inverse();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) entries.emplace_back(k + 3 + r, k + 3 + c, j_inv(r, c));
  }
  const int n = 6 * static_cast<int>(model.bodies.size());
  Eigen::SparseMatrix<double> m_inv(n, n);
  m_inv.setFromTriplets(entries.begin(), entries.end());
  return m_inv;
}

}  // namespace mbrt::codegen
