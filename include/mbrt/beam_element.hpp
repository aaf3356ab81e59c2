// An elastic beam element between two bodies in a convected (co-rotational)
// frame: the nodal beams of Downer, Park & Chiou (1992, "Dynamics of flexible
// beams for multibody systems: a computational procedure", CMAME 96), for
// large motions with small strains in each element.
//
// Each end carries a triad T = R Q (its body's rotation times the element's
// axes in body axes: x along the element, y and z its bending axes). The
// strains, all in element axes:
//   stretch   e = |d| / l0 - 1                 (d: end 1 to end 2)
//   shear     g = ((T1 + T2) / 2)^T d / l0, its y and z
//   rotation  k = vee(Rr - Rr^T) / 2, Rr = T1^T T2 (torsion about x, bending about y, z)
// and the energy U = l0 / 2 (EA e^2 + GAy gy^2 + GAz gz^2) + k^T diag(GJ, EIy, EIz) k / (2 l0).
// The forces and torques are U's exact gradient, so a free beam keeps its
// energy, momentum and angular momentum (the shear measured with the mean
// triad does not lock in bending). Damping is stiffness-proportional on the
// stretch and rotation rates.
#pragma once

#include "mbrt/forces.hpp"
#include "mbrt/joints.hpp"

namespace mbrt {

struct BeamElement {
  Vec3 s1, s2;    // ends, body axes (from each body's centre of mass)
  Mat3 Q1, Q2;    // element axes in body 1's and body 2's axes
  double l0;      // unstrained length, m
  double EA, GAy, GAz, GJ, EIy, EIz;
  double damping; // s: stiffness-proportional
};

struct BeamElementLoad {
  Vec3 f2;        // force on body 2 at its end (body 1 gets -f2 at its end), world
  Vec3 tau1, tau2;  // torques besides the end forces' moments, body axes
  double energy;
};

namespace beam_detail {
inline Vec3 vee_of_skew_part(const Mat3& A) noexcept {
  return 0.5 * Vec3(A(2, 1) - A(1, 2), A(0, 2) - A(2, 0), A(1, 0) - A(0, 1));
}
}  // namespace beam_detail

inline BeamElementLoad beam_element(const BeamElement& e, const BodyMotion& m1, const BodyMotion& m2) noexcept {
  const CarriedVector p1 = carried_point(m1.pose, m1.vel, e.s1);
  const CarriedVector p2 = carried_point(m2.pose, m2.vel, e.s2);
  const Vec3 d = p2.x - p1.x;
  const double length = d.norm();
  const Mat3 T1 = m1.pose.R * e.Q1, T2 = m2.pose.R * e.Q2;
  // Stretch: tension along the chord.
  const Vec3 n = length > 0.0 ? Vec3(d / length) : Vec3(T1.col(0));
  const double stretch = length / e.l0 - 1.0;
  const double stretch_rate = n.dot(p2.x_dot - p1.x_dot) / e.l0;
  const double tension = e.EA * (stretch + e.damping * stretch_rate);
  // Shear against the mean triad.
  const Mat3 T_mean = 0.5 * (T1 + T2);
  const Vec3 g = T_mean.transpose() * d / e.l0;
  const Vec3 shear(0.0, e.GAy * g.y(), e.GAz * g.z());  // element axes
  // Rotation: torsion and bending, with their rate (the ends' relative angular velocity).
  const Mat3 Rr = T1.transpose() * T2;
  const Vec3 k = beam_detail::vee_of_skew_part(Rr);
  const Vec3 k_rate = T1.transpose() * (m2.pose.R * m2.vel.w - m1.pose.R * m1.vel.w);
  const Vec3 stiffness(e.GJ, e.EIy, e.EIz);
  const Vec3 moment = stiffness.cwiseProduct(k + e.damping * k_rate) / e.l0;
  // Gradients: dk = (tr(Rr) I - Rr^T) Q2^T dphi2 / 2 for body 2's body-axis
  // rotation, -(tr(Rr) I - Rr) Q1^T dphi1 / 2 for body 1's; the shear's
  // triads turn with their bodies: d(T^T d) = Q^T (R^T d)~ dphi.
  const Mat3 trace_minus = Rr.trace() * Mat3::Identity() - Rr;
  BeamElementLoad out;
  out.f2 = -tension * n - T_mean * shear;
  const Vec3 x1 = m1.pose.R.transpose() * d, x2 = m2.pose.R.transpose() * d;
  out.tau1 = 0.5 * x1.cross(e.Q1 * shear) + 0.5 * e.Q1 * (trace_minus.transpose() * moment);
  out.tau2 = 0.5 * x2.cross(e.Q2 * shear) - 0.5 * e.Q2 * (trace_minus * moment);
  out.energy = 0.5 * e.l0 * (e.EA * stretch * stretch + e.GAy * g.y() * g.y() + e.GAz * g.z() * g.z()) +
               0.5 * k.dot(stiffness.cwiseProduct(k)) / e.l0;
  return out;
}

}  // namespace mbrt
