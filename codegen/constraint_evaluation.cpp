#include "constraint_evaluation.hpp"

#include <stdexcept>

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

template <int N>
void stack(const mbrt::ConstraintRows<N>& rows, const ConstraintBlock& block, StackedConstraints& out) {
  out.phi.segment<N>(block.first_row) = rows.phi;
  out.phi_t.segment<N>(block.first_row) = rows.phi_t;
  if (block.body1 != kGround) out.B.block<N, 6>(block.first_row, 6 * block.body1) += rows.J1;
  if (block.body2 != kGround) out.B.block<N, 6>(block.first_row, 6 * block.body2) += rows.J2;
}

// The runtime kernel named by the block, as the generated code calls it.
void evaluate_block(const ConstraintBlock& b, const mbrt::BodyMotion& m1, const mbrt::BodyMotion& m2, double t,
                    StackedConstraints& out) {
  const std::string& k = b.kernel;
  const mbrt::JointFrame& f = b.frame;
  if (k == "spherical") return stack(mbrt::spherical(f, m1, m2), b, out);
  if (k == "revolute") return stack(mbrt::revolute(f, m1, m2), b, out);
  if (k == "universal") return stack(mbrt::universal(f, m1, m2), b, out);
  if (k == "cylindrical") return stack(mbrt::cylindrical(f, m1, m2), b, out);
  if (k == "prismatic") return stack(mbrt::prismatic(f, m1, m2), b, out);
  if (k == "fixed") return stack(mbrt::fixed(f, m1, m2), b, out);
  if (k == "distance") return stack(mbrt::distance(f, m1, m2), b, out);
  if (k == "screw") return stack(mbrt::screw(f, m1, m2), b, out);
  if (k == "planar") return stack(mbrt::planar(f, m1, m2), b, out);
  if (k == "rolling_disk") return stack(mbrt::rolling_disk(f, m1, m2), b, out);
  if (k == "knife_edge") return stack(mbrt::knife_edge(f, m1, m2), b, out);
  if (k == "rolling_ball") return stack(mbrt::rolling_ball(f, m1, m2), b, out);
  if (k == "velocity_toward") return stack(mbrt::velocity_toward(f, m1, m2), b, out);
  const mbrt::TimeValue target = evaluate(*b.function, t);
  if (k == "joint_angle_driver") return stack(mbrt::joint_angle_driver(f, m1, m2, target), b, out);
  if (k == "joint_distance_driver") return stack(mbrt::joint_distance_driver(f, m1, m2, target), b, out);
  if (k == "distance_driver") return stack(mbrt::distance_driver(f, m1, m2, target), b, out);
  throw std::logic_error("no kernel named " + k);
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
    evaluate_block(block, {a.pose, a.vel}, {b.pose, b.vel}, t, out);
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
