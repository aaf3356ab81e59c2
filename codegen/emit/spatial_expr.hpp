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
inline M3 skew(const V3& r) { return {V3{0.0, -r[2], r[1]}, V3{r[2], 0.0, -r[0]}, V3{-r[1], r[0], 0.0}}; }
inline V3 constant(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
inline M3 constant(const Eigen::Matrix3d& m) {
  return {V3{m(0, 0), m(0, 1), m(0, 2)}, V3{m(1, 0), m(1, 1), m(1, 2)}, V3{m(2, 0), m(2, 1), m(2, 2)}};
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
// about the COM (Featherstone eq. 2.63).
inline Inertia rigid_inertia(double m, const Eigen::Vector3d& c, const Eigen::Matrix3d& ic) {
  const Eigen::Matrix3d cx = (Eigen::Matrix3d() << 0, -c.z(), c.y(), c.z(), 0, -c.x(), -c.y(), c.x(), 0).finished();
  return {constant(Eigen::Matrix3d(ic + m * cx * cx.transpose())), constant(Eigen::Matrix3d(m * cx)),
          constant(Eigen::Matrix3d(m * Eigen::Matrix3d::Identity()))};
}

// Coordinates turned by E (new = E old): inertia E I E^T... expressed as the
// congruence with E^T: in the old axes, I_old = E^T I_new E.
inline Inertia to_old_axes(const M3& e, const Inertia& I) {
  return {congruence(e, I.A, true), congruence(e, I.B, false), congruence(e, I.C, true)};
}

// The origin moved from r (old origin's coordinates) to 0: with rx = skew(r),
// A' = A + rx B^T + (rx B^T)^T + rx^T C rx, B' = B + rx C, C' = C.
inline Inertia to_origin(const V3& r, const Inertia& I) {
  const M3 rx = skew(r);
  const M3 k = product(rx, transpose(I.B));
  const M3 rcr = congruence(rx, I.C, true);
  Inertia out = I;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) out.A[i][j] = out.A[j][i] = I.A[i][j] + k[i][j] + k[j][i] + rcr[i][j];
  out.B = I.B + product(rx, I.C);
  return out;
}

}  // namespace mbrt::codegen::spatial
