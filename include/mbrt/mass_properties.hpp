// Products with the constant block-diagonal inverse mass matrix
// M^-1 = blockdiag(I/m, J^-1) of one body, specialised by mass-property type.
#pragma once

#include "mbrt/forces.hpp"

namespace mbrt {

inline Vec6 inverse_mass_times(const PointMass& b, const Wrench& w) noexcept {
  Vec6 a;
  a << w.f / b.m, Vec3::Zero();
  return a;
}

template <class Inertia>
inline Vec6 inverse_mass_times(const Inertia& b, const Wrench& w) noexcept {
  Vec6 a;
  a << w.f / b.m, inverse_inertia_times(b, w.tau);
  return a;
}

// M^-1 J^T for a constraint block J (N x 6) of this body.
template <int N>
inline Eigen::Matrix<double, 6, N> inverse_mass_times_transpose(const PointMass& b,
                                                                const Eigen::Matrix<double, N, 6>& J) noexcept {
  Eigen::Matrix<double, 6, N> x;
  x.template topRows<3>() = J.template leftCols<3>().transpose() / b.m;
  x.template bottomRows<3>().setZero();
  return x;
}

template <int N>
inline Eigen::Matrix<double, 6, N> inverse_mass_times_transpose(const PrincipalInertia& b,
                                                                const Eigen::Matrix<double, N, 6>& J) noexcept {
  Eigen::Matrix<double, 6, N> x;
  x.template topRows<3>() = J.template leftCols<3>().transpose() / b.m;
  x.template bottomRows<3>() = J.template rightCols<3>().transpose().array().colwise() / b.J.array();
  return x;
}

template <int N>
inline Eigen::Matrix<double, 6, N> inverse_mass_times_transpose(const FullInertia& b,
                                                                const Eigen::Matrix<double, N, 6>& J) noexcept {
  Eigen::Matrix<double, 6, N> x;
  x.template topRows<3>() = J.template leftCols<3>().transpose() / b.m;
  x.template bottomRows<3>() = b.J_inv * J.template rightCols<3>().transpose();
  return x;
}

// Kinetic energy 1/2 u^T M u.
inline double kinetic_energy(const PointMass& b, const Vec6& u) noexcept {
  return 0.5 * b.m * u.head<3>().squaredNorm();
}

template <class Inertia>
inline double kinetic_energy(const Inertia& b, const Vec6& u) noexcept {
  const Vec3 w = u.tail<3>();
  return 0.5 * b.m * u.head<3>().squaredNorm() + 0.5 * w.dot(inertia_times(b, w));
}

}  // namespace mbrt
