// Torque-free rotation of a rigid body over one step, for the explicit stage
// of the staggered schemes (docs/stability.md).
//
// The gyroscopic torque -w x J w is not applied as a load: a light body
// spinning fast about a small principal moment makes it a stiff, skew
// (energy-conserving) term that an explicit or fixed-point treatment turns
// into growth. Instead the drift advances (p, w) by the free rotation of the
// body, split as in Dullweber, Leimkuhler and McLachlan 1997 ("Symplectic
// splitting methods for rigid body molecular dynamics", J. Chem. Phys.
// 107(15), 5840), into flows that are rotations at constant rates: with pi the
// body-frame angular momentum and I_r the middle principal moment,
//   T = |pi|^2 / (2 I_r) + sum over the other two axes a of pi_a^2 (1/I_a - 1/I_r) / 2.
// The first term turns the body about pi, which stays put; each other term
// turns it about its axis a and turns pi the other way. They are composed
// symmetrically, T_a(h/2) T_b(h/2) T_r(h) T_b(h/2) T_a(h/2). For a body with
// two equal moments (a rod, a disk) T_b vanishes, the flows commute and the
// rotation is exact: the spin about the symmetry axis cannot drift, however
// small its moment. Each angle is the Cayley angle 4 atan(theta / 4) of
// theta = tau * rate: a function of quantities the flow keeps, so each sub-map
// is the exact flow of a nearby energy and the composition keeps |pi| to
// round-off and the kinetic energy bounded for every spin rate.
#pragma once

#include "mbrt/body_state.hpp"
#include "mbrt/rotation.hpp"

namespace mbrt {

// The flow of pi_a^2 d / 2 for time tau about principal axis a (0, 1, 2):
// p <- p * q, pi <- R(q)^T pi, q the Cayley rotation by tau pi_a d.
inline void principal_axis_flow(EulerParameters& p, Vec3& pi, int a, double d, double tau) noexcept {
  const int j = (a + 1) % 3, k = (a + 2) % 3;
  const double t = 0.25 * tau * pi[a] * d;  // theta / 4
  const double inv = 1.0 / (1.0 + t * t);
  const double c = (1.0 - t * t) * inv, s = 2.0 * t * inv;  // cos and sin of half the angle
  EulerParameters q = EulerParameters::Zero();
  q[0] = c;
  q[1 + a] = s;
  p = quaternion_product(p, q);
  const double cos_angle = c * c - s * s, sin_angle = 2.0 * c * s;
  const double pj = pi[j], pk = pi[k];
  pi[j] = cos_angle * pj + sin_angle * pk;
  pi[k] = cos_angle * pk - sin_angle * pj;
}

// The symmetric composition over h, in `updates` equal sub-steps: p maps
// principal axes to world, pi is the angular momentum in principal axes and
// moments the principal moments.
inline void principal_frame_rotation(EulerParameters& p, Vec3& pi, const Vec3& moments, double h,
                                     int updates) noexcept {
  // r: the middle moment; a, b: the other two.
  int r = 0;
  for (int i = 0; i < 3; ++i) {
    const int n = (moments[i] > moments[0]) + (moments[i] > moments[1]) + (moments[i] > moments[2]);
    const int e = (moments[i] == moments[0]) + (moments[i] == moments[1]) + (moments[i] == moments[2]);
    if (n <= 1 && n + e >= 2) r = i;  // at least one moment below-or-equal and one above-or-equal
  }
  const int a = (r + 1) % 3, b = (r + 2) % 3;
  const double dr = 1.0 / moments[r], da = 1.0 / moments[a] - dr, db = 1.0 / moments[b] - dr;
  const double tau = h / updates;
  for (int n = 0; n < updates; ++n) {
    principal_axis_flow(p, pi, a, da, 0.5 * tau);
    principal_axis_flow(p, pi, b, db, 0.5 * tau);
    p = quaternion_product(p, cayley_increment((tau * dr) * pi));
    principal_axis_flow(p, pi, b, db, 0.5 * tau);
    principal_axis_flow(p, pi, a, da, 0.5 * tau);
  }
}

// Advances the Euler parameters p and the body-frame angular velocity w of a
// torque-free body by h. Body axes are principal.
inline void free_rotation(const PrincipalInertia& b, EulerParameters& p, Vec3& w, double h, int updates) noexcept {
  Vec3 pi = b.J.cwiseProduct(w);
  principal_frame_rotation(p, pi, b.J, h, updates);
  w = pi.cwiseQuotient(b.J);
  p /= p.norm();
}

// Body axes are not principal: the flows run in the principal frame, given by
// the constant Euler parameters b.principal_axes (principal to body axes).
inline void free_rotation(const FullInertia& b, EulerParameters& p, Vec3& w, double h, int updates) noexcept {
  const Mat3 q = rotation_matrix(b.principal_axes);
  EulerParameters p_principal = quaternion_product(p, b.principal_axes);
  Vec3 pi = q.transpose() * (b.J * w);
  principal_frame_rotation(p_principal, pi, b.principal_moments, h, updates);
  EulerParameters to_body = b.principal_axes;
  to_body.tail<3>() = -to_body.tail<3>();
  p = quaternion_product(p_principal, to_body);
  p /= p.norm();
  w = b.J_inv * (q * pi);
}

}  // namespace mbrt
