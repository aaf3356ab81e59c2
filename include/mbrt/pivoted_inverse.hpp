// The inverse of a small fixed-size matrix by Gauss-Jordan elimination with
// partial pivoting: the position stage's Newton matrix keeps its diagonal
// blocks inverted (codegen/emit/emit_newton.cpp). For blocks of up to six
// rows this is a few dozen operations, where Eigen's general LU goes through
// its blocked routines for large matrices. The rows are exchanged
// unconditionally (a row with itself where the pivot is already in place),
// so the work does not depend on the values.
#pragma once

#include <cmath>

#include <Eigen/Core>

namespace mbrt {

// A := A^-1. A singular A gives non-finite entries (the step's checks catch them).
template <int N>
inline void invert_with_pivoting(Eigen::Matrix<double, N, N>& A) noexcept {
  Eigen::Matrix<double, N, N> inverse = Eigen::Matrix<double, N, N>::Identity();
  for (int c = 0; c < N; ++c) {
    int pivot = c;
    for (int r = c + 1; r < N; ++r) pivot = std::abs(A(r, c)) > std::abs(A(pivot, c)) ? r : pivot;
    A.row(c).swap(A.row(pivot));
    inverse.row(c).swap(inverse.row(pivot));
    const double scale = 1.0 / A(c, c);
    A.row(c) *= scale;
    inverse.row(c) *= scale;
    for (int r = 0; r < N; ++r) {
      if (r == c) continue;
      const double f = A(r, c);
      A.row(r) -= f * A.row(c);
      inverse.row(r) -= f * inverse.row(c);
    }
  }
  A = inverse;
}

}  // namespace mbrt
