// Spatial vector algebra (Featherstone 2008, "Rigid Body Dynamics
// Algorithms", chapter 2) over generation-time symbolic values: what the
// staggered-tree emitter runs to record the recursion's straight-line code.
// Motions are [angular; linear at the frame origin], forces [moment about
// the origin; force], both in the frame's axes.
#pragma once

#include <array>

#include <Eigen/Core>

#include "straight_line.hpp"

namespace mbrt::codegen::spatial {

using V3 = std::array<Expr, 3>;
using M3 = std::array<V3, 3>;  // rows

inline V3 operator+(const V3& a, const V3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline V3 operator-(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline V3 operator*(const Expr& k, const V3& a) { return {k * a[0], k * a[1], k * a[2]}; }
inline Expr dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline V3 times(const M3& m, const V3& v) { return {dot(m[0], v), dot(m[1], v), dot(m[2], v)}; }
inline V3 column(const M3& m, int j) { return {m[0][j], m[1][j], m[2][j]}; }
inline V3 transpose_times(const M3& m, const V3& v) { return {dot(column(m, 0), v), dot(column(m, 1), v), dot(column(m, 2), v)}; }
inline M3 transpose(const M3& m) { return {column(m, 0), column(m, 1), column(m, 2)}; }
inline M3 operator+(const M3& a, const M3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline M3 product(const M3& a, const M3& b) {
  M3 p;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) p[i][j] = dot(a[i], column(b, j));
  return p;
}
// E^T X E; for a symmetric X only the upper triangle is computed.
inline M3 congruence(const M3& e, const M3& x, bool symmetric) {
  const M3 xe = product(x, e);
  M3 p;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) p[i][j] = symmetric && j < i ? p[j][i] : dot(column(e, i), column(xe, j));
  return p;
}
// E^T X E for E a turn in the plane of axes i and j (E_ii = E_jj = c,
// E_ij = -E_ji = s, the third axis k left alone). In that plane X's symmetric
// part turns by the double angle (cos 2phi = c^2 - s^2, sin 2phi = 2 c s)
// and its antisymmetric part not at all, which costs about half the
// products of the plain congruence.
inline M3 plane_congruence(const M3& x, size_t i, size_t j, const Expr& c, const Expr& s, bool symmetric) {
  const size_t k = 3 - i - j;
  const Expr cs = c * s, c2 = c * c - s * s;
  const Expr s2 = 2.0 * cs, c2_half = 0.5 * c2;
  const Expr sum = x[i][i] + x[j][j], d = x[i][i] - x[j][j];
  M3 p;
  // With sigma the symmetric and kappa the antisymmetric part of x_ij:
  // p_ii = sum / 2 + d cos / 2 - sigma sin, p_ij = d sin / 2 + sigma cos + kappa.
  if (symmetric && c.is_constant() && s.is_constant()) {
    // A constant turn: c^2 and s^2 fold, and a zero entry of x drops its term.
    p[i][i] = (c * c) * x[i][i] + (s * s) * x[j][j] - s2 * x[i][j];
    p[i][j] = p[j][i] = cs * d + c2 * x[i][j];
  } else if (symmetric) {
    p[i][i] = sum * 0.5 + c2_half * d - s2 * x[i][j];
    p[i][j] = p[j][i] = cs * d + c2 * x[i][j];
  } else {
    const Expr sigma2 = x[i][j] + x[j][i], kappa = 0.5 * (x[i][j] - x[j][i]);
    p[i][i] = sum * 0.5 + c2_half * d - cs * sigma2;
    const Expr sym = cs * d + c2_half * sigma2;
    p[i][j] = sym + kappa;
    p[j][i] = sym - kappa;
  }
  p[j][j] = sum - p[i][i];
  p[i][k] = c * x[i][k] - s * x[j][k];
  p[j][k] = s * x[i][k] + c * x[j][k];
  p[k][i] = symmetric ? p[i][k] : c * x[k][i] - s * x[k][j];
  p[k][j] = symmetric ? p[j][k] : s * x[k][i] + c * x[k][j];
  p[k][k] = x[k][k];
  return p;
}
inline M3 skew(const V3& r) { return {V3{0.0, -r[2], r[1]}, V3{r[2], 0.0, -r[0]}, V3{-r[1], r[0], 0.0}}; }
inline V3 constant(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
inline M3 constant(const Eigen::Matrix3d& m) {
  return {V3{m(0, 0), m(0, 1), m(0, 2)}, V3{m(1, 0), m(1, 1), m(1, 2)}, V3{m(2, 0), m(2, 1), m(2, 2)}};
}

// Euler parameters [e0; e] and the rotation they describe (Hamilton product,
// scalar first).
using Quaternion = std::array<Expr, 4>;
inline Quaternion constant(const Eigen::Vector4d& e) { return {e[0], e[1], e[2], e[3]}; }
inline Quaternion quaternion_product(const Quaternion& a, const Quaternion& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3], a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1], a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}
// The matrix of unit Euler parameters: 1 - 2 (e2^2 + e3^2), ... (the diagonal
// uses |e| = 1).
inline M3 rotation_matrix(const Quaternion& e) {
  const Expr x = 2.0 * e[1], y = 2.0 * e[2], z = 2.0 * e[3];
  const Expr xx = x * e[1], yy = y * e[2], zz = z * e[3];
  const Expr xy = x * e[2], xz = x * e[3], yz = y * e[3];
  const Expr wx = x * e[0], wy = y * e[0], wz = z * e[0];
  return {V3{1.0 - (yy + zz), xy - wz, xz + wy}, V3{xy + wz, 1.0 - (xx + zz), yz - wx},
          V3{xz - wy, yz + wx, 1.0 - (xx + yy)}};
}

struct Motion {
  V3 w, v;
};
struct Wrench {
  V3 n, f;
};
inline Motion operator+(const Motion& a, const Motion& b) { return {a.w + b.w, a.v + b.v}; }
inline Wrench operator+(const Wrench& a, const Wrench& b) { return {a.n + b.n, a.f + b.f}; }
inline Wrench operator-(const Wrench& a, const Wrench& b) { return {a.n - b.n, a.f - b.f}; }
inline Expr component(const Motion& m, int k) { return k < 3 ? m.w[static_cast<size_t>(k)] : m.v[static_cast<size_t>(k - 3)]; }
inline Expr component(const Wrench& f, int k) { return k < 3 ? f.n[static_cast<size_t>(k)] : f.f[static_cast<size_t>(k - 3)]; }

// Spatial cross products: v x m and v x* f.
inline Motion cross(const Motion& v, const Motion& m) { return {cross(v.w, m.w), cross(v.w, m.v) + cross(v.v, m.w)}; }
inline Wrench cross(const Motion& v, const Wrench& f) { return {cross(v.w, f.n) + cross(v.v, f.f), cross(v.w, f.f)}; }

// A symmetric 6 x 6 inertia [A B; B^T C] about the frame origin.
struct Inertia {
  M3 A, B, C;
  Expr at(int i, int j) const {
    if (i > j) return at(j, i);
    if (j < 3) return A[static_cast<size_t>(i)][static_cast<size_t>(j)];
    if (i >= 3) return C[static_cast<size_t>(i - 3)][static_cast<size_t>(j - 3)];
    return B[static_cast<size_t>(i)][static_cast<size_t>(j - 3)];
  }
  void set(int i, int j, const Expr& x) {
    if (i > j) return set(j, i, x);
    if (j < 3) A[static_cast<size_t>(i)][static_cast<size_t>(j)] = A[static_cast<size_t>(j)][static_cast<size_t>(i)] = x;
    else if (i >= 3) C[static_cast<size_t>(i - 3)][static_cast<size_t>(j - 3)] = C[static_cast<size_t>(j - 3)][static_cast<size_t>(i - 3)] = x;
    else B[static_cast<size_t>(i)][static_cast<size_t>(j - 3)] = x;
  }
};
inline Inertia operator+(const Inertia& a, const Inertia& b) { return {a.A + b.A, a.B + b.B, a.C + b.C}; }
inline Wrench times(const Inertia& I, const Motion& m) {
  return {times(I.A, m.w) + times(I.B, m.v), transpose_times(I.B, m.w) + times(I.C, m.v)};
}

// A rigid body's inertia about the frame origin: mass m, COM c, inertia Ic
// about the COM (Featherstone eq. 2.63). The first form folds the sums of
// known values; the second takes a mass and an inertia the generated code
// reads (runtime parameters).
inline Inertia rigid_inertia(double m, const Eigen::Vector3d& c, const Eigen::Matrix3d& ic) {
  const Eigen::Matrix3d cx = (Eigen::Matrix3d() << 0, -c.z(), c.y(), c.z(), 0, -c.x(), -c.y(), c.x(), 0).finished();
  return {constant(Eigen::Matrix3d(ic + m * cx * cx.transpose())), constant(Eigen::Matrix3d(m * cx)),
          constant(Eigen::Matrix3d(m * Eigen::Matrix3d::Identity()))};
}
inline Inertia rigid_inertia(const Expr& m, const Eigen::Vector3d& c, const M3& ic) {
  const Eigen::Matrix3d cx = (Eigen::Matrix3d() << 0, -c.z(), c.y(), c.z(), 0, -c.x(), -c.y(), c.x(), 0).finished();
  const M3 ccx = constant(Eigen::Matrix3d(cx * cx.transpose()));
  Inertia out;
  for (size_t i = 0; i < 3; ++i) {
    for (size_t j = 0; j < 3; ++j) {
      out.A[i][j] = ic[i][j] + m * ccx[i][j];
      out.B[i][j] = m * cx(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
      out.C[i][j] = i == j ? m : Expr(0.0);
    }
  }
  return out;
}

// A rigid body's bias force v x* (I v) (mass m, COM c, inertia Ic about the
// COM): with p = m (v + w x c) the COM's momentum, the Jacobi identity turns
// it into [w x (Ic w) + c x (w x p); w x p], fewer products than I v first.
inline Wrench rigid_bias(const Expr& m, const Eigen::Vector3d& c, const M3& ic, const Motion& v) {
  const V3 com = constant(c);
  const V3 g = cross(v.w, m * (v.v + cross(v.w, com)));
  return {cross(v.w, times(ic, v.w)) + cross(com, g), g};
}

// Coordinates turned by E (new = E old): inertia E I E^T... expressed as the
// congruence with E^T: in the old axes, I_old = E^T I_new E.
inline Inertia to_old_axes(const M3& e, const Inertia& I) {
  return {congruence(e, I.A, true), congruence(e, I.B, false), congruence(e, I.C, true)};
}
// The same for E a turn in the plane of axes i and j (plane_congruence).
inline Inertia to_old_axes(size_t i, size_t j, const Expr& c, const Expr& s, const Inertia& I) {
  return {plane_congruence(I.A, i, j, c, s, true), plane_congruence(I.B, i, j, c, s, false),
          plane_congruence(I.C, i, j, c, s, true)};
}

// The origin moved from r (old origin's coordinates) to 0: with rx = skew(r),
// A' = A + rx B^T + (rx B^T)^T + rx^T C rx, B' = B + rx C, C' = C.
inline Inertia to_origin(const V3& r, const Inertia& I) {
  const M3 rx = skew(r);
  const M3 k = product(rx, transpose(I.B));
  const M3 rcr = congruence(rx, I.C, true);
  Inertia out = I;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) out.A[i][j] = out.A[j][i] = I.A[i][j] + (i == j ? 2.0 * k[i][i] : k[i][j] + k[j][i]) + rcr[i][j];
  out.B = I.B + product(rx, I.C);
  return out;
}

}  // namespace mbrt::codegen::spatial
