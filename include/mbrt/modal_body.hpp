// A modal flexible body (docs/flexible.md): a body frame's motion plus N
// modal coordinates q of a beam clamped to the frame at its root, in the
// floating frame of reference (Jerkovsky 1978, "The structure of multibody
// dynamics equations", J. Guidance Control 1(3); the inertia invariants of
// Shabana 2005, Dynamics of Multibody Systems, ch. 5).
//
// The frame is the undeformed beam's centre of mass and axes (x along the
// beam). A material point at rho0 moves to rho0 + Psi q + sigma(q) +
// beta(q) x e_x: the modes' linear field, and the bending's shortening,
// which draws the mass towards the root, taken as an affine field with the
// shortening's first two moments: a shift sigma of the whole mass, and for
// a beam a stretch beta along it (x from the centre). The mass matrix in
// (v body, w body, qdot) is that field's Gram matrix, so it stays positive
// definite whatever the deflection,
//   M(q) = [m I, -[c]x, St(q); [c]x, J(q), Sr(q); St(q)^T, Sr(q)^T, M_qq(q)],
// and the centrifugal, Coriolis and gyroscopic terms are loads. Nothing in
// it lags: a light frame (a tool's root section) would otherwise feed its own
// last accelerations back through q. The step keeps the frame's generalized
// velocities and the modal momentum p = M_qq qdot + St(q)^T R^T v +
// Sr(q)^T w, which constraint forces on the frame leave alone; the frame
// then moves with the reduced mass Mf(q) - S M_qq^-1 S^T (Mf the frame's
// 6x6 block, S = [St(q); Sr(q)]) and the load F - S M_qq^-1 f_q, where f_q
// is the modes' generalized force.
//
// Geometric stiffness (Kane, Ryan & Banerjee 1987): the stresses of the
// frame's rigid motion, from its spin and its acceleration less gravity,
// with precomputed matrices per load case. Those of the acceleration are the
// Hessians D_a of the body's first moment: bending shortens the body and
// shifts its mass back, c(q) = St q + (q^T D_a q / 2)_a = St q + m sigma(q).
// So they enter through the mass matrix, and the frame's acceleration is the
// step's own, not the last step's (which a welded loop's undamped modes fed
// on). A beam's spin cases are the Hessian of the shortening's second
// moment, int x s dm, which the stretch carries: the spin stiffens the modes
// through the kinetic energy, which the step keeps. A structure from a file
// keeps its spin cases as loads at the spin of the moment.
#pragma once

#include <array>

#include "mbrt/body_state.hpp"
#include "mbrt/dense_cholesky.hpp"
#include "mbrt/forces.hpp"
#include "mbrt/joints.hpp"
#include "mbrt/rotation.hpp"

namespace mbrt {

template <int N>
struct ModalBody {
  using Modes = Eigen::Matrix<double, N, 1>;
  using ModeMatrix = Eigen::Matrix<double, N, N>;
  Eigen::Matrix<double, N, 3> St_T, Sr_T;       // St^T, Sr^T at q = 0
  Modes stiffness;                              // omega_i^2
  Modes damping;                                // 1/s: modal damping
  // Geometric stiffness per load case: per w_a w_b (xx, yy, zz, xy, xz, yz),
  // then per m/s^2 of the frame's acceleration less gravity along x, y, z
  // (body axes); bit k of kg_cases set where case k is not zero. The
  // acceleration cases are the Hessians D_a of the first moment
  // c(q) = St q + (q^T D_a q / 2)_a.
  std::array<ModeMatrix, 9> kg;
  unsigned kg_cases = 0;
  // A beam's stretch along x, beta(q) = q^T stretch q / 2 per unit x, which
  // carries the spin's geometric stiffness in the mass (modal_mass), its
  // cases then zero; axial_moment = int x^2 dm, zero where there is none.
  ModeMatrix stretch;
  double axial_moment = 0.0;
  std::array<ModeMatrix, 9> E;                  // int Psi_a^T Psi_b dm, index 3 a + b
  std::array<Eigen::Matrix<double, 1, N>, 9> G; // int rho0_a Psi_b dm, index 3 a + b
  Mat3 J;                                       // the undeformed body's inertia about its centre, body axes
  double m;
};

namespace modal_detail {

// X_ab = sum over the 9 (a, b) of T[3a + b] applied to q, qd, ...
template <int N>
inline Mat3 field_product(const std::array<Eigen::Matrix<double, 1, N>, 9>& G, const Eigen::Matrix<double, N, 1>& q) noexcept {
  Mat3 X;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) X(a, b) = (G[static_cast<size_t>(3 * a + b)] * q)(0);
  return X;
}

template <int N>
inline Mat3 field_product(const std::array<Eigen::Matrix<double, N, N>, 9>& E, const Eigen::Matrix<double, N, 1>& x,
                          const Eigen::Matrix<double, N, 1>& y) noexcept {
  Mat3 X;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) X(a, b) = x.dot(E[static_cast<size_t>(3 * a + b)] * y);
  return X;
}

inline Vec3 vee_of(const Mat3& P) noexcept { return {P(1, 2) - P(2, 1), P(2, 0) - P(0, 2), P(0, 1) - P(1, 0)}; }

inline constexpr unsigned kAccelerationCase = 6;  // kg[6 + a]: per unit acceleration along a

template <int N>
inline bool has_case(const ModalBody<N>& b, unsigned k) noexcept {
  return (b.kg_cases & (1u << k)) != 0;
}

// The linear field's Sr^T = (int (rho0 + Psi q) x Psi)^T: row j is
// int (rho0 + Psi q) x Psi_j, whose component i is e_iab (q^T E_ab)_j.
template <int N>
inline Eigen::Matrix<double, N, 3> turn_coupling_transpose(const ModalBody<N>& b, const Eigen::Matrix<double, N, 1>& q) noexcept {
  Eigen::Matrix<double, N, 3> T = b.Sr_T;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    T.col(i) += (q.transpose() * (b.E[static_cast<size_t>(3 * j + k)] - b.E[static_cast<size_t>(3 * k + j)])).transpose();
  }
  return T;
}

// int x Psi dm (3 x N): row a is G_xa.
template <int N>
inline Eigen::Matrix<double, 3, N> axial_moments(const ModalBody<N>& b) noexcept {
  Eigen::Matrix<double, 3, N> Gx;
  for (int a = 0; a < 3; ++a) Gx.row(a) = b.G[static_cast<size_t>(a)];
  return Gx;
}

// The linear field's inertia about the frame's origin, body axes.
template <int N>
inline Mat3 field_inertia(const ModalBody<N>& b, const Eigen::Matrix<double, N, 1>& q) noexcept {
  const Mat3 X = field_product<N>(b.G, q);    // int rho0 u^T
  const Mat3 W = field_product<N>(b.E, q, q);  // int u u^T
  return b.J + (2.0 * X.trace() + W.trace()) * Mat3::Identity() - X - X.transpose() - W;
}

}  // namespace modal_detail

// d sigma / dq at q = x (sigma is quadratic, so this is linear in x): row a
// is (D_a x)^T / m, D_a the first moment's Hessian (the acceleration cases).
template <int N>
inline Eigen::Matrix<double, 3, N> shortening_columns(const ModalBody<N>& b, const Eigen::Matrix<double, N, 1>& x) noexcept {
  Eigen::Matrix<double, 3, N> g = Eigen::Matrix<double, 3, N>::Zero();
  for (unsigned a = 0; a < 3; ++a) {
    if (modal_detail::has_case(b, modal_detail::kAccelerationCase + a))
      g.row(a) = (b.kg[modal_detail::kAccelerationCase + a] * x).transpose() / b.m;
  }
  return g;
}

// The mass matrix's q-dependent blocks at q (body axes): those of the linear
// field rho0 + Psi q shifted by sigma(q) = (q^T D_a q / (2 m))_a and, where
// the body has one, stretched by beta(q) x e_x, a Gram matrix whatever q.
// The shift's rate columns are g = d sigma / dq, so
// St(q) = St + m g, M_qq = I + m g^T g + g^T St + St^T g, and with
// c_lin = St q, c = c_lin + m sigma:
//   J(q) = J_lin(q) - m [sigma]x^2 - [sigma]x [c_lin]x - [c_lin]x [sigma]x,
//   Sr(q) = Sr_lin(q) + [sigma]x St(q) + [c_lin]x g.
template <int N>
struct ModalMass {
  using ModeMatrix = Eigen::Matrix<double, N, N>;
  Vec3 sigma, c, c_lin;
  Eigen::Matrix<double, 3, N> g;           // d sigma / dq
  double beta = 0.0;                       // the stretch along x per unit x
  Eigen::Matrix<double, N, 1> h;           // d beta / dq
  Vec3 moment_x;                           // int x (rho0 + Psi q) dm
  Mat3 J, J_lin;
  Eigen::Matrix<double, N, 3> St_T, Sr_T;  // St(q)^T, Sr(q)^T
  ModeMatrix L;                            // M_qq = L L^T (lower triangle)
};

// M_qq^-1 X.
template <int N, int K>
inline Eigen::Matrix<double, N, K> modal_solve(const ModalMass<N>& mm, Eigen::Matrix<double, N, K> X) noexcept {
  solve_factored<N, K>(mm.L, X);
  return X;
}

template <int N>
inline ModalMass<N> modal_mass(const ModalBody<N>& b, const Eigen::Matrix<double, N, 1>& q) noexcept {
  ModalMass<N> mm;
  mm.g = shortening_columns<N>(b, q);
  mm.sigma = 0.5 * mm.g * q;
  mm.c_lin = b.St_T.transpose() * q;
  mm.c = mm.c_lin + b.m * mm.sigma;
  mm.J_lin = modal_detail::field_inertia<N>(b, q);
  const Mat3 S = skew(mm.sigma), C = skew(mm.c_lin);
  mm.J = mm.J_lin - b.m * S * S - S * C - C * S;
  mm.St_T = b.St_T + b.m * mm.g.transpose();
  mm.Sr_T = modal_detail::turn_coupling_transpose<N>(b, q) - mm.St_T * S - mm.g.transpose() * C;
  const Eigen::Matrix<double, N, N> St_g = b.St_T * mm.g;
  Eigen::Matrix<double, N, N> M_qq = Eigen::Matrix<double, N, N>::Identity() + b.m * mm.g.transpose() * mm.g + St_g + St_g.transpose();
  if (b.axial_moment > 0.0) {
    // The stretch delta = beta x e_x: with m_x = int x (rho0 + Psi q),
    // J gains 2 beta m_x,x I - beta (m_x e_x^T + e_x m_x^T) + beta^2 int x^2 (I - e_x e_x^T),
    // Sr's column j h_j m_x x e_x + beta e_x x int x Psi_j, and M_qq
    // G_x h^T + h G_x^T + int x^2 h h^T (G_x = int x Psi_x).
    const Eigen::Matrix<double, 3, N> Gx = modal_detail::axial_moments<N>(b);
    const Vec3 ex = Vec3::UnitX();
    mm.h = b.stretch * q;
    mm.beta = 0.5 * q.dot(mm.h);
    mm.moment_x = b.axial_moment * ex + Gx * q;
    const Vec3& mx = mm.moment_x;
    const double beta = mm.beta, theta = b.axial_moment;
    mm.J += 2.0 * beta * mx.x() * Mat3::Identity() - beta * (mx * ex.transpose() + ex * mx.transpose()) +
            beta * beta * theta * (Mat3::Identity() - ex * ex.transpose());
    mm.Sr_T += mm.h * mx.cross(ex).transpose() + beta * (skew(ex) * Gx).transpose();
    const Eigen::Matrix<double, N, N> Gh = Gx.row(0).transpose() * mm.h.transpose();
    M_qq += Gh + Gh.transpose() + theta * mm.h * mm.h.transpose();
  } else {
    mm.h.setZero();
    mm.moment_x.setZero();
  }
  cholesky_in_place<N>(M_qq);  // a Gram matrix: positive definite
  mm.L = M_qq.template triangularView<Eigen::Lower>();
  return mm;
}

// The modal rates qdot from the momentum p and the frame's velocities.
template <int N>
inline Eigen::Matrix<double, N, 1> modal_rates(const ModalMass<N>& mm, const Mat3& R, const Vec3& v, const Vec3& w,
                                               const Eigen::Matrix<double, N, 1>& p) noexcept {
  return modal_solve<N, 1>(mm, p - mm.St_T * (R.transpose() * v) - mm.Sr_T * w);
}

template <int N>
inline Eigen::Matrix<double, N, 1> modal_rates(const ModalBody<N>& b, const Mat3& R, const Vec3& v, const Vec3& w,
                                               const Eigen::Matrix<double, N, 1>& q,
                                               const Eigen::Matrix<double, N, 1>& p) noexcept {
  return modal_rates<N>(modal_mass<N>(b, q), R, v, w, p);
}

// q's change over a drift of h at the half-step velocities (R the frame's
// turn averaged over the step): qdot at the mid-step q, which Sr(q) needs
// for second order.
template <int N>
inline Eigen::Matrix<double, N, 1> modal_drift(const ModalBody<N>& b, const Mat3& R, const Vec3& v, const Vec3& w,
                                               const Eigen::Matrix<double, N, 1>& q,
                                               const Eigen::Matrix<double, N, 1>& p, double h) noexcept {
  const Eigen::Matrix<double, N, 1> start_rate = modal_rates<N>(b, R, v, w, q, p);
  return h * modal_rates<N>(b, R, v, w, q + (0.5 * h) * start_rate, p);
}

// M^-1 of the frame's 6 velocities in (v world, w body): the R-turned
// inverse of the reduced mass Mf(q) - S(q) M_qq^-1 S(q)^T, body axes.
struct ModalInverseMass {
  Eigen::Matrix<double, 6, 6> reduced_inverse;
  Mat3 R;
};

// The frame's reduced mass Mf(q) - S(q) M_qq(q)^-1 S(q)^T in (v body, w body).
template <int N>
inline Eigen::Matrix<double, 6, 6> modal_reduced_mass(const ModalBody<N>& b, const ModalMass<N>& mm) noexcept {
  // S M_qq^-1 S^T = W W^T with W = S L^-T.
  Eigen::Matrix<double, 6, N> W;
  W << mm.St_T.transpose(), mm.Sr_T.transpose();
  solve_right_lower_transposed<6, N>(mm.L, W);
  const Mat3 c = skew(mm.c);
  Eigen::Matrix<double, 6, 6> reduced = -W * W.transpose();
  reduced.template topLeftCorner<3, 3>().diagonal().array() += b.m;
  reduced.template topRightCorner<3, 3>() -= c;
  reduced.template bottomLeftCorner<3, 3>() += c;
  reduced.template bottomRightCorner<3, 3>() += mm.J;
  return reduced;
}

template <int N>
inline Eigen::Matrix<double, 6, 6> modal_reduced_mass(const ModalBody<N>& b, const Eigen::Matrix<double, N, 1>& q) noexcept {
  return modal_reduced_mass<N>(b, modal_mass<N>(b, q));
}

// M^-1 of the frame's 6 velocities as the step applies it, from the mass
// at the body's deformation and its frame's turn R.
template <int N>
inline ModalInverseMass modal_inverse_mass(const ModalBody<N>& b, const ModalMass<N>& mm, const Mat3& R) noexcept {
  Eigen::Matrix<double, 6, 6> L = modal_reduced_mass<N>(b, mm), inverse = Eigen::Matrix<double, 6, 6>::Identity();
  cholesky_in_place<6>(L);  // a Gram matrix's Schur complement: positive definite
  solve_factored<6, 6>(L, inverse);
  return {inverse, R};
}

template <int N>
inline ModalInverseMass modal_inverse_mass(const ModalBody<N>& b, const EulerParameters& p,
                                           const Eigen::Matrix<double, N, 1>& q) noexcept {
  return modal_inverse_mass<N>(b, modal_mass<N>(b, q), rotation_matrix(p));
}

inline Vec6 inverse_mass_times(const ModalInverseMass& b, const Wrench& w) noexcept {
  Vec6 body;
  body << b.R.transpose() * w.f, w.tau;
  const Vec6 a = b.reduced_inverse * body;
  Vec6 out;
  out << b.R * a.head<3>(), a.tail<3>();
  return out;
}

template <int K>
inline Eigen::Matrix<double, 6, K> inverse_mass_times_transpose(const ModalInverseMass& b,
                                                                const Eigen::Matrix<double, K, 6>& J) noexcept {
  Eigen::Matrix<double, 6, K> body;
  body.template topRows<3>() = b.R.transpose() * J.template leftCols<3>().transpose();
  body.template bottomRows<3>() = J.template rightCols<3>().transpose();
  Eigen::Matrix<double, 6, K> x = b.reduced_inverse * body;
  x.template topRows<3>() = b.R * x.template topRows<3>();
  return x;
}

template <int N>
struct ModalLoad {
  Eigen::Matrix<double, N, 1> momentum_rate;  // dp/dt
  double potential;                           // strain energy, gravity of the deformation
};

namespace modal_detail {

// The frame of the linear field (the frame's origin shifted by sigma), in
// body axes: its velocity, the body's momentum, and the shift's
// acceleration where the frame's and the modes' accelerations are zero.
struct ShiftedFrame {
  Vec3 velocity, momentum, shift_acceleration;
};

template <int N>
inline ShiftedFrame shifted_frame(const ModalBody<N>& b, const ModalMass<N>& mm, const Vec3& vb, const Vec3& w,
                                  const Eigen::Matrix<double, N, 1>& qd, const Eigen::Matrix<double, 3, N>& g_rate) noexcept {
  const Vec3 shift_rate = mm.g * qd;
  ShiftedFrame s;
  s.velocity = vb + w.cross(mm.sigma) + shift_rate;
  s.momentum = b.m * s.velocity + w.cross(mm.c_lin) + b.St_T.transpose() * qd;
  s.shift_acceleration = w.cross(w.cross(mm.sigma)) + 2.0 * w.cross(shift_rate) + g_rate * qd;
  return s;
}

// The stretch's share of the kinetic energy, T_d = A . k + int x^2 |k|^2 / 2
// with k = beta (w x e_x) + beta_dot e_x its velocity per unit x and
// A = w x m_x + int x Psi qdot, and of the equations it adds (Lagrange's, and
// Euler's for the frame's turn): the turn's momentum H = dT_d/dw, dT_d/dq,
// the rate of its momenta at constant velocities (M_dot y), and the biases
// M_dot y + w x H for the turn, M_dot y - dT_d/dq for the modes.
template <int N>
struct StretchTerms {
  double energy = 0.0;
  Vec3 bias_w = Vec3::Zero();
  Eigen::Matrix<double, N, 1> bias_q, energy_gradient, mass_rate_q;
};

template <int N>
inline StretchTerms<N> stretch_terms(const ModalBody<N>& b, const ModalMass<N>& mm, const Vec3& w,
                                     const Eigen::Matrix<double, N, 1>& qd) noexcept {
  StretchTerms<N> t;
  t.bias_q.setZero(), t.energy_gradient.setZero(), t.mass_rate_q.setZero();
  if (!(b.axial_moment > 0.0)) return t;
  const Eigen::Matrix<double, 3, N> Gx = axial_moments<N>(b);
  const Vec3 ex = Vec3::UnitX(), w_ex = w.cross(ex);
  const double theta = b.axial_moment, beta_rate = mm.h.dot(qd);
  const Eigen::Matrix<double, N, 1> h_rate = b.stretch * qd;
  const Vec3 k = mm.beta * w_ex + beta_rate * ex, A = w.cross(mm.moment_x) + Gx * qd, Pi = A + theta * k;
  const Vec3 H = mm.moment_x.cross(k) + mm.beta * ex.cross(Pi);
  const Vec3 mx_rate = Gx * qd, k_rate = beta_rate * w_ex + qd.dot(h_rate) * ex;
  const Vec3 Pi_rate = w.cross(mx_rate) + theta * k_rate;
  t.energy = A.dot(k) + 0.5 * theta * k.squaredNorm();
  t.energy_gradient = Gx.transpose() * k.cross(w) + mm.h * w_ex.dot(Pi) + h_rate * Pi.x();
  t.mass_rate_q = Gx.transpose() * k_rate + h_rate * Pi.x() + mm.h * Pi_rate.x();
  t.bias_q = t.mass_rate_q - t.energy_gradient;
  t.bias_w = mx_rate.cross(k) + mm.moment_x.cross(k_rate) + beta_rate * ex.cross(Pi) + mm.beta * ex.cross(Pi_rate) + w.cross(H);
  return t;
}

}  // namespace modal_detail

// Adds the body's centrifugal, Coriolis, gyroscopic, elastic and damping
// terms to its frame load (force world, torque body), reduced by the modes'
// generalized force, and returns the modal momentum's rate. g is gravity;
// applied is the modes' generalized force of the loads at its nodes
// (modal_point_force), whose frame parts load already holds.
//
// The terms are the linear field's in its own frame, whose origin the
// shortening shifts by sigma(q) (velocity vs = vb + w x sigma + g qdot),
// carried back by that shift's transpose: a force there is the same force,
// its torque about the frame's origin gains sigma x f and its modal force
// g^T f; the shift's acceleration at zero accelerations, kappa, is an
// inertia load. dp/dt = dT/dq + Q (q are true coordinates), the linear
// field's dT/dq plus the shift's, (d vs / dq)^T P with P the momentum.
// mm is the mass at q.
template <int N>
inline ModalLoad<N> modal_loads(const ModalBody<N>& b, const ModalMass<N>& mm, const Mat3& R, const Vec3& v, const Vec3& w,
                                const Vec3& g, const Eigen::Matrix<double, N, 1>& q, const Eigen::Matrix<double, N, 1>& p,
                                const Eigen::Matrix<double, N, 1>& applied, Wrench& load) noexcept {
  using Modes = Eigen::Matrix<double, N, 1>;
  const Vec3 vb = R.transpose() * v, gb = R.transpose() * g;
  const Modes qd = modal_rates<N>(mm, R, v, w, p);
  const Eigen::Matrix<double, 3, N> g_rate = shortening_columns<N>(b, qd);
  const modal_detail::ShiftedFrame s = modal_detail::shifted_frame<N>(b, mm, vb, w, qd, g_rate);
  const Vec3 &c = mm.c_lin, cd = b.St_T.transpose() * qd, &kappa = s.shift_acceleration;  // int u, int udot
  const Mat3 P = modal_detail::field_product<N>(b.G, qd) + modal_detail::field_product<N>(b.E, q, qd);  // int rho udot^T
  // The linear field's centrifugal, Coriolis and gyroscopic terms, and the shift's inertia.
  const Vec3 f = -(w.cross(w.cross(c)) + 2.0 * w.cross(cd)) - b.m * kappa;
  const Vec3 tau = -(w.cross(mm.J_lin * w) + 2.0 * (P.trace() * w - P.transpose() * w)) - c.cross(kappa);
  // Modal: the generalized forces (the spin's geometric stiffness, elastic,
  // damping, gravity on the first moment), centrifugal.
  const std::array<double, 6> spin = {w.x() * w.x(), w.y() * w.y(), w.z() * w.z(), w.x() * w.y(), w.x() * w.z(), w.y() * w.z()};
  Modes Q = applied + mm.St_T * gb - b.stiffness.cwiseProduct(q) - b.damping.cwiseProduct(qd);
  for (unsigned k = 0; k < spin.size(); ++k) {
    if (modal_detail::has_case(b, k)) Q -= spin[k] * (b.kg[k] * q);
  }
  Modes centrifugal = Modes::Zero();
  const double w2 = w.squaredNorm();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double product = w[i] * w[j] - (i == j ? w2 : 0.0);
      const size_t ij = static_cast<size_t>(3 * i + j), ji = static_cast<size_t>(3 * j + i);
      if (product != 0.0) centrifugal -= product * (b.G[ji].transpose() + b.E[ij] * q);
    }
  }
  // int Psi^T (w x udot): component i of w x udot is w_j udot_k - w_k udot_j,
  // (i, j, k) cyclic. Twice that is the Coriolis force; once, the turn of
  // Sr(q)^T w in p.
  Modes coriolis = Modes::Zero();
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    coriolis += (w[j] * b.E[static_cast<size_t>(3 * i + k)] - w[k] * b.E[static_cast<size_t>(3 * i + j)]) * qd;
  }
  const modal_detail::StretchTerms<N> stretch = modal_detail::stretch_terms<N>(b, mm, w, qd);
  const Modes fq = Q + centrifugal - 2.0 * coriolis - b.St_T * kappa + mm.g.transpose() * f - stretch.bias_q;
  const Modes reduced = modal_solve<N, 1>(mm, fq);
  load.f += R * (f - mm.St_T.transpose() * reduced);
  load.tau += tau + mm.sigma.cross(f) + mm.c.cross(gb) - stretch.bias_w - mm.Sr_T.transpose() * reduced;
  const Modes rate = Q + centrifugal - coriolis + b.St_T * s.velocity.cross(w) + g_rate.transpose() * s.momentum -
                     mm.g.transpose() * w.cross(s.momentum) + stretch.energy_gradient;
  return {rate, 0.5 * q.dot(b.stiffness.cwiseProduct(q)) - gb.dot(mm.c)};
}

template <int N>
inline ModalLoad<N> modal_loads(const ModalBody<N>& b, const Mat3& R, const Vec3& v, const Vec3& w, const Vec3& g,
                                const Eigen::Matrix<double, N, 1>& q, const Eigen::Matrix<double, N, 1>& p,
                                const Eigen::Matrix<double, N, 1>& applied, Wrench& load) noexcept {
  return modal_loads<N>(b, modal_mass<N>(b, q), R, v, w, g, q, p, applied, load);
}

// The body's kinetic energy: the linear field's in its shifted frame.
template <int N>
inline double modal_kinetic_energy(const ModalBody<N>& b, const Mat3& R, const Vec3& v, const Vec3& w,
                                   const Eigen::Matrix<double, N, 1>& q, const Eigen::Matrix<double, N, 1>& p) noexcept {
  const ModalMass<N> mm = modal_mass<N>(b, q);
  const Eigen::Matrix<double, N, 1> qd = modal_rates<N>(mm, R, v, w, p);
  const Vec3 vs = R.transpose() * v + w.cross(mm.sigma) + mm.g * qd, cd = b.St_T.transpose() * qd;
  const Mat3 P = modal_detail::field_product<N>(b.G, qd) + modal_detail::field_product<N>(b.E, q, qd);
  return 0.5 * b.m * vs.squaredNorm() + vs.dot(w.cross(mm.c_lin) + cd) + 0.5 * w.dot(mm.J_lin * w) +
         w.dot(modal_detail::vee_of(P)) + 0.5 * qd.squaredNorm() + modal_detail::stretch_terms<N>(b, mm, w, qd).energy;
}
// A node's section turns by the small rotation theta = Theta q: by C(theta),
// the rotation of Gibbs vector theta / 2 (Cayley's map; to first order the
// turn by theta), in the frame's axes, whose angular velocity there
// (C_dot = [omega]x C) is exactly omega = T(theta) theta_dot with
// T = lambda (I + [theta]x / 2), lambda = 1 / (1 + |theta|^2 / 4). The
// node's pose and velocity outputs and the joints there take this turn.
struct SectionTurn {
  Mat3 C;         // the section's axes in the frame's
  Mat3 T;         // omega = T theta_dot
  Vec3 omega;     // the section's angular velocity relative to the frame, body axes
  Vec3 bias;      // omega_dot - T theta_ddot = -lambda (theta . theta_dot) omega / 2
};

inline SectionTurn section_turn(const Vec3& theta, const Vec3& theta_dot = Vec3::Zero()) noexcept {
  const double lambda = 1.0 / (1.0 + 0.25 * theta.squaredNorm());
  const Mat3 X = skew(theta);
  SectionTurn t;
  t.C = Mat3::Identity() + lambda * (X + 0.5 * X * X);
  t.T = lambda * (Mat3::Identity() + 0.5 * X);
  t.omega = t.T * theta_dot;
  t.bias = (-0.5 * lambda * theta.dot(theta_dot)) * t.omega;
  return t;
}

// C(theta) as Euler parameters: (1, theta / 2) normalized.
inline EulerParameters section_turn_parameters(const Vec3& theta) noexcept {
  EulerParameters c;
  c << 1.0, 0.5 * theta;
  return c / c.norm();
}

// A node of the beam: undeformed place in body axes, and its displacement
// and small rotation per modal coordinate.
template <int N>
struct ModalPoint {
  Vec3 point;
  Eigen::Matrix<double, 3, N> displacement, rotation;
};

// The point's pose: x, y, z (world), then e0..e3 of its section.
template <int N>
inline void modal_point_pose(const ModalPoint<N>& c, const RigidState& s, const Eigen::Matrix<double, N, 1>& q,
                             double* out) noexcept {
  Eigen::Map<Vec3> position(out);
  Eigen::Map<EulerParameters> orientation(out + 3);
  position = s.r + rotation_matrix(s.p) * (c.point + c.displacement * q);
  orientation = quaternion_product(s.p, section_turn_parameters(c.rotation * q));
}

// The point's velocity (world) and its section's angular velocity (the frame's axes).
template <int N>
inline void modal_point_velocity(const ModalBody<N>& b, const ModalPoint<N>& c, const RigidState& s,
                                 const Eigen::Matrix<double, N, 1>& q, const Eigen::Matrix<double, N, 1>& p,
                                 double* out) noexcept {
  const Mat3 R = rotation_matrix(s.p);
  const Eigen::Matrix<double, N, 1> qd = modal_rates<N>(b, R, s.v, s.w, q, p);
  Eigen::Map<Vec3> velocity(out), angular_velocity(out + 3);
  velocity = s.v + R * (s.w.cross(c.point + c.displacement * q) + c.displacement * qd);
  angular_velocity = s.w + section_turn(c.rotation * q, c.rotation * qd).omega;
}

// A force f (world) at node c: the frame's load (force world, torque body
// about the frame's origin) gains it at the node's deformed place; returns
// the modes' generalized force Psi^T R^T f, for modal_loads' applied.
template <int N>
inline Eigen::Matrix<double, N, 1> modal_point_force(const ModalPoint<N>& c, const Mat3& R,
                                                     const Eigen::Matrix<double, N, 1>& q, const Vec3& f,
                                                     Wrench& load) noexcept {
  const Vec3 fb = R.transpose() * f;
  load.f += f;
  load.tau += (c.point + c.displacement * q).cross(fb);
  return c.displacement.transpose() * fb;
}

// A torque t (world) on node c: the frame's load takes it, and the modes
// their share Theta^T R^T t through the node's small rotations (the linear
// theory's; section_turn's T differs from I at second order in the turn),
// returned for modal_loads' applied.
template <int N>
inline Eigen::Matrix<double, N, 1> modal_point_torque(const ModalPoint<N>& c, const Mat3& R, const Vec3& t,
                                                      Wrench& load) noexcept {
  const Vec3 tb = R.transpose() * t;
  load.tau += tb;
  return c.rotation.transpose() * tb;
}

// Node c as a force element or a joint sees it: its deformed place and its
// section's turn in body axes, and a velocity of a rigid body that carries
// that place and the turned axes as the node moves: the section's angular
// velocity w + omega, and the frame's velocity with the node's deformation
// rate R (Psi qdot - omega x place), so that the carried place moves at the
// node's velocity. The modal rates qdot ride along for modal_node_rows.
template <int N>
struct ModalPointMotion {
  Vec3 point;
  SectionTurn turn;
  Eigen::Matrix<double, N, 1> rates;
  BodyVelocity velocity;
};

template <int N>
inline ModalPointMotion<N> modal_point_motion(const ModalBody<N>& b, const ModalPoint<N>& c, const BodyPose& pose,
                                              const BodyVelocity& vel, const Eigen::Matrix<double, N, 1>& q,
                                              const Eigen::Matrix<double, N, 1>& p) noexcept {
  const Eigen::Matrix<double, N, 1> qd = modal_rates<N>(b, pose.R, vel.v, vel.w, q, p);
  const Vec3 point = c.point + c.displacement * q;
  const SectionTurn turn = section_turn(c.rotation * q, c.rotation * qd);
  return {point, turn, qd, {vel.v + pose.R * (c.displacement * qd - turn.omega.cross(point)), vel.w + turn.omega}};
}

// Joint frame f with the axes on a node's side (side 1 or 2) carried by its
// section's turn.
inline JointFrame turned_joint_frame(JointFrame f, int side, const Mat3& turn) noexcept {
  Vec3* axes[2][3] = {{&f.a1, &f.b1, &f.c1}, {&f.a2, &f.b2, &f.c2}};
  for (Vec3* a : axes[side - 1]) *a = turn * *a;
  return f;
}

// Node c's section turn at q, in the frame's axes.
template <int N>
inline Mat3 modal_section_turn(const ModalPoint<N>& c, const Eigen::Matrix<double, N, 1>& q) noexcept {
  return section_turn(c.rotation * q).C;
}

// Jp S^T: what the momentum columns Jp = Jq M_qq^-1 take from the frame's
// columns. The step's velocities are the frame's (v world, w body) and the
// modal momenta p = M_qq qdot + S^T (v, w), S^T = [St(q)^T R^T, Sr(q)^T], so a
// row Jq qdot reads -Jp S^T (v, w) + Jp p.
template <int N, int K>
inline Eigen::Matrix<double, K, 6> modal_frame_share(const ModalMass<N>& mm, const Mat3& R,
                                                     const Eigen::Matrix<double, K, 6>& Jp) noexcept {
  Eigen::Matrix<double, N, 6> S_T;
  S_T << mm.St_T * R.transpose(), mm.Sr_T;
  Eigen::Matrix<double, K, 6> share;
  share = Jp.template leftCols<N>() * S_T;
  return share;
}

template <int N, int K>
inline Eigen::Matrix<double, K, 6> modal_frame_share(const ModalBody<N>& b, const Mat3& R, const Eigen::Matrix<double, N, 1>& q,
                                                     const Eigen::Matrix<double, K, 6>& Jp) noexcept {
  return modal_frame_share<N, K>(modal_mass<N>(b, q), R, Jp);
}

// Rows of a joint at node c of a modal body, from a kernel's rows J (frame's
// columns: J_v the place's velocity, J_w the section's angular velocity) for
// the rigid body modal_point_motion describes, `node`. With omega = T Theta qdot
// (section_turn) and s the deformed place, the kernel's velocity columns
// read J_v (v + R (Psi qdot + s x omega)) + J_w (w + omega), so the rows gain
// the modal columns Jq = J_v R (Psi + [s]x T Theta) + J_w T Theta (returned
// in the first N of 6 columns: the modes' generalized force is Jq^T lambda)
// and, through qdot = M_qq^-1 (p - S^T (v, w)), the momentum columns
// Jp = Jq M_qq^-1 (momentum_columns), while the frame's columns lose Jp S^T
// (modal_frame_share). The place accelerates at
//   v_dot + R (w_dot x s + Psi q_ddot + w x (w x s) + 2 w x Psi q_dot),
// the axes turn at w_dot + T Theta q_ddot + bias + w x omega; with
// q_ddot = M_qq^-1 (p_dot - S^T (v_dot, w_dot) + St(q)^T (w x R^T v) - M_dot y),
// M_dot y the rate of p at constant velocities y = (R^T v, w, qdot), quad
// gains what the kernel, which turns both at w + omega, leaves out.
template <int N, int K>
inline Eigen::Matrix<double, K, 6> modal_node_rows(const ModalBody<N>& b, const ModalPoint<N>& c, const BodyPose& pose,
                                                   const BodyVelocity& vel, const Eigen::Matrix<double, N, 1>& q,
                                                   const ModalPointMotion<N>& node, Eigen::Matrix<double, K, 6>& J,
                                                   Eigen::Matrix<double, K, 1>& quad,
                                                   Eigen::Matrix<double, K, 6>& momentum_columns) noexcept {
  const ModalMass<N> mm = modal_mass<N>(b, q);
  const Eigen::Matrix<double, N, 1>& qd = node.rates;
  const Eigen::Matrix<double, K, 3> Jv = J.template leftCols<3>(), Jw = J.template rightCols<3>();
  const Vec3 &s = node.point, u_dot = c.displacement * qd, &w = vel.w;
  const SectionTurn& turn = node.turn;
  const Eigen::Matrix<double, 3, N> turn_columns = turn.T * c.rotation;
  Eigen::Matrix<double, K, 6> Jq = Eigen::Matrix<double, K, 6>::Zero();
  Jq.template leftCols<N>() = Jv * (pose.R * (c.displacement + skew(s) * turn_columns)) + Jw * turn_columns;
  momentum_columns.setZero();
  momentum_columns.template leftCols<N>() = modal_solve<N, K>(mm, Jq.template leftCols<N>().transpose()).transpose();
  J -= modal_frame_share<N, K>(mm, pose.R, momentum_columns);
  // M_dot y: the shift's terms (modal_loads' shifted frame) and the linear
  // field's Sr_lin(q_dot) w.
  const Vec3 vb = pose.R.transpose() * vel.v, cd = b.St_T.transpose() * qd;
  const Eigen::Matrix<double, 3, N> g_rate = shortening_columns<N>(b, qd);
  const modal_detail::ShiftedFrame shifted = modal_detail::shifted_frame<N>(b, mm, vb, w, qd, g_rate);
  const Vec3 shift_rate = w.cross(mm.g * qd) + g_rate * qd;
  const Eigen::Matrix<double, N, 1> mass_rate =
      g_rate.transpose() * shifted.momentum + mm.g.transpose() * (b.m * shift_rate + w.cross(cd)) + b.St_T * shift_rate +
      (modal_detail::turn_coupling_transpose<N>(b, qd) - b.Sr_T) * w + modal_detail::stretch_terms<N>(b, mm, w, qd).mass_rate_q;
  const Eigen::Matrix<double, N, 1> q_ddot_bias = modal_solve<N, 1>(mm, mm.St_T * w.cross(vb) - mass_rate);
  const Vec3& omega = turn.omega;
  const Vec3 place = 2.0 * w.cross(u_dot - omega.cross(s)) - omega.cross(omega.cross(s)) - turn.bias.cross(s);
  quad += Jw * (w.cross(omega) + turn.bias) + Jv * (pose.R * place) + Jq.template leftCols<N>() * q_ddot_bias;
  return Jq;
}

}  // namespace mbrt
