// Euler-parameter kinematics: rotation matrix, quaternion product and the
// closed-form Cayley (implicit-midpoint) update of Chiou 1990 ("Constraint
// treatment techniques and parallel algorithms for multibody dynamic analysis",
// PhD thesis, section 5.5.4).
#pragma once

#include "mbrt/types.hpp"

namespace mbrt {

// Body-to-world rotation matrix R(p): x_world = R * x_body.
// This is the transpose of Chiou 1990 eq. 2.6.5, which maps world to body.
inline Mat3 rotation_matrix(const EulerParameters& p) noexcept {
  const double e0 = p[0], e1 = p[1], e2 = p[2], e3 = p[3];
  Mat3 r;
  r << 1.0 - 2.0 * (e2 * e2 + e3 * e3), 2.0 * (e1 * e2 - e0 * e3), 2.0 * (e1 * e3 + e0 * e2),
       2.0 * (e1 * e2 + e0 * e3), 1.0 - 2.0 * (e1 * e1 + e3 * e3), 2.0 * (e2 * e3 - e0 * e1),
       2.0 * (e1 * e3 - e0 * e2), 2.0 * (e2 * e3 + e0 * e1), 1.0 - 2.0 * (e1 * e1 + e2 * e2);
  return r;
}

// Hamilton product a * b (scalar first).
inline EulerParameters quaternion_product(const EulerParameters& a, const EulerParameters& b) noexcept {
  EulerParameters c;
  c[0] = a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3];
  c[1] = a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2];
  c[2] = a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1];
  c[3] = a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0];
  return c;
}

// Unit quaternion of the Cayley map for a body-frame rotation increment theta
// (= h * w_body): the closed-form inverse of (I - h/4 Omega) p+ = (I + h/4 Omega) p,
// with p' = 1/2 p * (0, w). Orthogonal, so |p+| = |p| to round-off.
inline EulerParameters cayley_increment(const Vec3& theta) noexcept {
  const double x = 0.0625 * theta.squaredNorm();  // (|theta|/4)^2
  const double inv = 1.0 / (1.0 + x);
  EulerParameters c;
  c[0] = (1.0 - x) * inv;
  c.tail<3>() = (0.5 * inv) * theta;
  return c;
}

// p' = 1/2 p * (0, w): the Euler parameters' rate at body-frame angular
// velocity w (for any p, so a Runge-Kutta stage's p need not be unit).
inline EulerParameters euler_parameter_rate(const EulerParameters& p, const Vec3& w) noexcept {
  EulerParameters w4;
  w4 << 0.0, w;
  return 0.5 * quaternion_product(p, w4);
}

// Advances p by body-frame angular velocity w held constant over h, using
// `updates` Cayley sub-steps of h / updates each. More sub-steps approach the
// exact exponential map; the count is fixed at generation time. The map is
// orthogonal; the final rescaling only keeps round-off from accumulating.
inline EulerParameters advance_euler_parameters(const EulerParameters& p, const Vec3& w, double h,
                                                int updates) noexcept {
  const EulerParameters c = cayley_increment((h / updates) * w);
  EulerParameters q = p;
  for (int k = 0; k < updates; ++k) q = quaternion_product(q, c);
  return q / q.norm();
}

}  // namespace mbrt
