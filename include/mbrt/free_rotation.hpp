// Torque-free rotation of a rigid body over one step, for the explicit stage
// of the staggered schemes (docs/stability.md).
//
// The gyroscopic torque -w x J w is not applied as a load: a light body
// spinning fast about a small principal moment makes it a stiff, skew
// (energy-conserving) term that an explicit or fixed-point treatment turns
// into growth. Instead the step advances (p, w) by the free rotation of the
// body, split into the flows of its three principal kinetic energies
// T_i = pi_i^2 / (2 D_i), pi = body-frame angular momentum (Dullweber,
// Leimkuhler and McLachlan 1997, "Symplectic splitting methods for rigid body
// molecular dynamics", J. Chem. Phys. 107(15), the symmetric splitting of
// section III): T_1(h/2) T_2(h/2) T_3(h) T_2(h/2) T_1(h/2). Each flow is a
// rotation about one principal axis at the constant rate pi_i / D_i, which
// turns the body and turns pi the other way. The rotation angle here is the
// Cayley angle 4 atan(theta / 4) of theta = tau pi_i / D_i: since it depends
// on the conserved pi_i alone, each sub-map is still the exact flow of a
// nearby energy, so the composition stays a Poisson map that keeps |pi| to
// round-off and the kinetic energy within O(h^2) for every spin rate:
// nothing can grow without bound, however fast the body spins.
#pragma once

#include "mbrt/body_state.hpp"
#include "mbrt/rotation.hpp"

namespace mbrt {

// The flow of T_axis for time tau: p <- p * q, pi <- R(q)^T pi, with q the
// Cayley rotation about the principal axis `axis` by tau pi_axis / D_axis.
template <int Axis>
inline void principal_axis_flow(EulerParameters& p, Vec3& pi, double inverse_moment, double tau) noexcept {
  constexpr int j = (Axis + 1) % 3, k = (Axis + 2) % 3;
  const double t = 0.25 * tau * pi[Axis] * inverse_moment;  // theta / 4
  const double d = 1.0 / (1.0 + t * t);
  const double c = (1.0 - t * t) * d, s = 2.0 * t * d;  // cos and sin of half the rotation angle
  EulerParameters q = EulerParameters::Zero();
  q[0] = c;
  q[1 + Axis] = s;
  p = quaternion_product(p, q);
  const double cos_angle = c * c - s * s, sin_angle = 2.0 * c * s;
  const double pj = pi[j], pk = pi[k];
  pi[j] = cos_angle * pj + sin_angle * pk;
  pi[k] = cos_angle * pk - sin_angle * pj;
}

// The symmetric composition over h, in `updates` equal sub-steps, of the
// principal-frame flows: p maps principal axes to world, pi is the angular
// momentum in principal axes and inverse_moments are 1 / D_i.
inline void principal_frame_rotation(EulerParameters& p, Vec3& pi, const Vec3& inverse_moments, double h,
                                     int updates) noexcept {
  const double tau = h / updates;
  for (int n = 0; n < updates; ++n) {
    principal_axis_flow<0>(p, pi, inverse_moments[0], 0.5 * tau);
    principal_axis_flow<1>(p, pi, inverse_moments[1], 0.5 * tau);
    principal_axis_flow<2>(p, pi, inverse_moments[2], tau);
    principal_axis_flow<1>(p, pi, inverse_moments[1], 0.5 * tau);
    principal_axis_flow<0>(p, pi, inverse_moments[0], 0.5 * tau);
  }
}

// Advances the Euler parameters p and the body-frame angular velocity w of a
// torque-free body by h. Body axes are principal.
inline void free_rotation(const PrincipalInertia& b, EulerParameters& p, Vec3& w, double h, int updates) noexcept {
  Vec3 pi = b.J.cwiseProduct(w);
  principal_frame_rotation(p, pi, b.J.cwiseInverse(), h, updates);
  w = pi.cwiseQuotient(b.J);
  p /= p.norm();
}

// Body axes are not principal: the flows run in the principal frame, given by
// the constant Euler parameters b.principal_axes (principal to body axes).
inline void free_rotation(const FullInertia& b, EulerParameters& p, Vec3& w, double h, int updates) noexcept {
  const Mat3 q = rotation_matrix(b.principal_axes);
  EulerParameters p_principal = quaternion_product(p, b.principal_axes);
  Vec3 pi = q.transpose() * (b.J * w);
  principal_frame_rotation(p_principal, pi, b.principal_moments.cwiseInverse(), h, updates);
  EulerParameters to_body = b.principal_axes;
  to_body.tail<3>() = -to_body.tail<3>();
  p = quaternion_product(p_principal, to_body);
  p /= p.norm();
  w = b.J_inv * (q * pi);
}

}  // namespace mbrt
