// Fixed-size dense Cholesky pieces for the block factorization that the
// generator emits over the constant sparsity pattern of S = B M^-1 B^T.
#pragma once

#include <cmath>

#include <Eigen/Core>

namespace mbrt {

// In place: the lower triangle of A becomes L with A = L L^T. Returns false
// (and leaves a usable, finite factor) when a pivot is not positive.
template <int N>
inline bool cholesky_in_place(Eigen::Matrix<double, N, N>& A) noexcept {
  bool positive = true;
  for (int j = 0; j < N; ++j) {
    double d = A(j, j);
    for (int k = 0; k < j; ++k) d -= A(j, k) * A(j, k);
    if (!(d > 0.0)) {
      positive = false;
      d = 1.0;
    }
    const double l = std::sqrt(d);
    A(j, j) = l;
    for (int i = j + 1; i < N; ++i) {
      double s = A(i, j);
      for (int k = 0; k < j; ++k) s -= A(i, k) * A(j, k);
      A(i, j) = s / l;
    }
  }
  return positive;
}

// X := X L^-T (an off-diagonal block of the factor from its Schur update).
template <int R, int N>
inline void solve_right_lower_transposed(const Eigen::Matrix<double, N, N>& L,
                                         Eigen::Matrix<double, R, N>& X) noexcept {
  for (int j = 0; j < N; ++j) {
    for (int k = 0; k < j; ++k) X.col(j) -= L(j, k) * X.col(k);
    X.col(j) /= L(j, j);
  }
}

// y := L^-1 y
template <int N>
inline void solve_lower(const Eigen::Matrix<double, N, N>& L, Eigen::Matrix<double, N, 1>& y) noexcept {
  for (int i = 0; i < N; ++i) {
    for (int k = 0; k < i; ++k) y[i] -= L(i, k) * y[k];
    y[i] /= L(i, i);
  }
}

// y := L^-T y
template <int N>
inline void solve_lower_transposed(const Eigen::Matrix<double, N, N>& L, Eigen::Matrix<double, N, 1>& y) noexcept {
  for (int i = N - 1; i >= 0; --i) {
    for (int k = i + 1; k < N; ++k) y[i] -= L(k, i) * y[k];
    y[i] /= L(i, i);
  }
}

// X := (L L^T)^-1 X, column by column.
template <int N, int K>
inline void solve_factored(const Eigen::Matrix<double, N, N>& L, Eigen::Matrix<double, N, K>& X) noexcept {
  for (int j = 0; j < K; ++j) {
    Eigen::Matrix<double, N, 1> y = X.col(j);
    solve_lower(L, y);
    solve_lower_transposed(L, y);
    X.col(j) = y;
  }
}

}  // namespace mbrt
