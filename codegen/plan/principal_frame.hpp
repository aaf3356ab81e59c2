// The principal moments and axes of a body's inertia, for the free rotation
// of the explicit stage (include/mbrt/free_rotation.hpp) and the stable-step
// estimate of the step report.
#pragma once

#include <Eigen/Dense>

namespace mbrt::codegen {

struct PrincipalFrame {
  Eigen::Vector3d moments;  // about the principal axes, in their order
  Eigen::Vector4d axes;     // Euler parameters e0..e3 of the rotation from principal to body axes
};

// Body axes themselves when the inertia is diagonal (so a principal-axis body
// takes the same path whether or not the step is specialized for it), else
// the eigenvectors, ordered by ascending moment, as a proper rotation.
inline PrincipalFrame principal_frame(const Eigen::Matrix3d& inertia) {
  const Eigen::Matrix3d off = inertia - Eigen::Matrix3d(inertia.diagonal().asDiagonal());
  if (off.cwiseAbs().maxCoeff() == 0.0) return {inertia.diagonal(), Eigen::Vector4d(1, 0, 0, 0)};
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertia);
  Eigen::Matrix3d q = eig.eigenvectors();
  if (q.determinant() < 0.0) q.col(2) = -q.col(2);
  const Eigen::Quaterniond e(q);
  return {eig.eigenvalues(), Eigen::Vector4d(e.w(), e.x(), e.y(), e.z())};
}

}  // namespace mbrt::codegen
