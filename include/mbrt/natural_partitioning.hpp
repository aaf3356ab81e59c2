// Pieces of the staggered-nps scheme (docs/staggered-nps.md): the explicit
// null space of a tree joint's constraint Jacobian, built body by body from
// the joint type, and the 6 x 6 mass matrices the tree elimination works on.
// Velocities are u = [v (world); w (body axes)] as everywhere in the step.
#pragma once

#include "mbrt/forces.hpp"

namespace mbrt {

using Mat6 = Eigen::Matrix<double, 6, 6>;

inline Mat6 mass_matrix(const PrincipalInertia& b) noexcept {
  Mat6 m = Mat6::Zero();
  m.topLeftCorner<3, 3>().diagonal().setConstant(b.m);
  m.bottomRightCorner<3, 3>().diagonal() = b.J;
  return m;
}

inline Mat6 mass_matrix(const FullInertia& b) noexcept {
  Mat6 m = Mat6::Zero();
  m.topLeftCorner<3, 3>().diagonal().setConstant(b.m);
  m.bottomRightCorner<3, 3>() = b.J;
  return m;
}

// M u, the momentum of one body.
inline Vec6 mass_times(const PointMass& b, const Vec6& u) noexcept {
  Vec6 p;
  p << b.m * u.head<3>(), Vec3::Zero();
  return p;
}

template <class Inertia>
inline Vec6 mass_times(const Inertia& b, const Vec6& u) noexcept {
  Vec6 p;
  p << b.m * u.head<3>(), inertia_times(b, u.tail<3>());
  return p;
}

// M X, column by column: a leaf body's articulated inertia is its mass.
template <class Mass, int K>
inline Eigen::Matrix<double, 6, K> mass_times_columns(const Mass& b, const Eigen::Matrix<double, 6, K>& x) noexcept {
  Eigen::Matrix<double, 6, K> y;
  for (int c = 0; c < K; ++c) y.col(c) = mass_times(b, Vec6(x.col(c)));
  return y;
}

// M^-1 f for f = [force; torque], as a free body without children moves.
template <class Mass>
inline Vec6 inverse_mass_times(const Mass& b, const Vec6& f) noexcept {
  return inverse_mass_times(b, Wrench{f.head<3>(), f.tail<3>()});
}

inline Vec6 as_vector(const Wrench& w) noexcept {
  Vec6 f;
  f << w.f, w.tau;
  return f;
}

// X with u_child = X u_parent when the child moves rigidly with its parent:
// w_child = C w_p, C = R_c^T R_p. Kept dense: 6 x 6 products vectorize
// better than products with its 3 x 3 blocks.
//
// About the parent's COM (v_child = v_p + R_p (w_p x rho), rho the child's
// COM in parent axes), every relative quantity in the parent's axes stays
// constant, so B_parent + B_child X = 0 for the sliding joints at any
// configuration.
inline Mat6 rigid_transfer(const BodyPose& parent, const BodyPose& child) noexcept {
  const Vec3 rho = parent.R.transpose() * (child.r - parent.r);
  Mat6 x = Mat6::Zero();
  x.topLeftCorner<3, 3>().setIdentity();
  x.topRightCorner<3, 3>() = -parent.R * skew(rho);
  x.bottomRightCorner<3, 3>() = child.R.transpose() * parent.R;
  return x;
}

// The same motion anchored at the joint point instead (s_p, s_c: the joint
// point on each body): the child's point moves with the parent's, so joint
// points that have drifted apart keep their world offset and the
// coincidence rows' B_parent + B_child X = 0 holds exactly too.
inline Mat6 rigid_transfer(const BodyPose& parent, const BodyPose& child, const Vec3& s_p, const Vec3& s_c) noexcept {
  Mat6 x = Mat6::Zero();
  const Mat3 c = child.R.transpose() * parent.R;
  x.topLeftCorner<3, 3>().setIdentity();
  x.topRightCorner<3, 3>() = -parent.R * skew(s_p) + child.R * skew(s_c) * c;
  x.bottomRightCorner<3, 3>() = c;
  return x;
}

// Null-space columns of a joint's child-side Jacobian. A turn about the
// body-axes unit vector e through the body point s (s from the COM) moves
// the COM with R (s x e); a slide along e moves it with R e.
inline Vec6 turn_about(const BodyPose& child, const Vec3& s, const Vec3& e) noexcept {
  Vec6 h;
  h << child.R * s.cross(e), e;
  return h;
}

inline Vec6 slide_along(const BodyPose& child, const Vec3& e) noexcept {
  Vec6 h;
  h << child.R * e, Vec3::Zero();
  return h;
}

}  // namespace mbrt
