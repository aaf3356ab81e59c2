// Independent tests of dense_cholesky.hpp against Eigen's LLT, for N = 1..6.
// The references (Eigen's QR and LLT) work on dynamic-size matrices, so they
// are compiled once rather than once per N; the code under test is fixed-size.
#include <doctest/doctest.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <algorithm>
#include <random>
#include <vector>

#include "mbrt/dense_cholesky.hpp"

namespace {

template <int R, int C>
using Matrix = Eigen::Matrix<double, R, C>;
using Eigen::MatrixXd;

class Random {
 public:
  explicit Random(unsigned seed) : gen_(seed) {}
  template <int R, int C>
  Matrix<R, C> matrix() {
    return matrix(R, C);
  }
  MatrixXd matrix(int rows, int cols) {
    MatrixXd m(rows, cols);
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j) m(i, j) = std::uniform_real_distribution<double>(-1.0, 1.0)(gen_);
    return m;
  }
  // Random orthogonal matrix from the QR factorization of a random matrix.
  template <int N>
  Matrix<N, N> orthogonal() {
    return orthogonal(N);
  }
  MatrixXd orthogonal(int n) {
    return Eigen::HouseholderQR<MatrixXd>(matrix(n, n)).householderQ() * MatrixXd::Identity(n, n);
  }

 private:
  std::mt19937 gen_;
};

// Symmetric positive definite with eigenvalues in [0.1, 2.1] scaled by `scale`.
MatrixXd random_spd(Random& rnd, int n, double scale) {
  const MatrixXd Q = rnd.orthogonal(n);
  const Eigen::VectorXd lambda = (rnd.matrix(n, 1).array() + 1.1).matrix() * scale;
  return Q * lambda.asDiagonal() * Q.transpose();
}

template <int N>
Matrix<N, N> random_spd(Random& rnd, double scale) {
  return random_spd(rnd, N, scale);
}

template <int N>
Matrix<N, N> lower_of(const Matrix<N, N>& A) {
  return A.template triangularView<Eigen::Lower>();
}

template <int N>
void check_factor_and_solves(Random& rnd) {
  INFO("N = " << N);
  for (int trial = 0; trial < 20; ++trial) {
    const double scale = trial % 2 == 0 ? 1.0 : 1e3;
    const Matrix<N, N> A = random_spd<N>(rnd, scale);
    Matrix<N, N> F = A;
    REQUIRE(mbrt::cholesky_in_place<N>(F));
    const Matrix<N, N> L = lower_of<N>(F);
    const Eigen::LLT<MatrixXd> llt(A);
    REQUIRE(llt.info() == Eigen::Success);
    const double tol = 1e-13 * scale;

    CHECK((L * L.transpose() - A).cwiseAbs().maxCoeff() < tol);
    CHECK((L - Matrix<N, N>(llt.matrixL())).cwiseAbs().maxCoeff() < 1e-12 * std::sqrt(scale));
    CHECK(L.diagonal().minCoeff() > 0.0);

    const Matrix<N, 1> b = rnd.matrix<N, 1>();
    Matrix<N, 1> y = b;
    mbrt::solve_lower<N>(L, y);
    const Matrix<N, 1> y_ref = llt.matrixL().solve(b);
    CHECK((y - y_ref).cwiseAbs().maxCoeff() < 1e-12 * std::max(1.0, y_ref.cwiseAbs().maxCoeff()));

    Matrix<N, 1> z = b;
    mbrt::solve_lower_transposed<N>(L, z);
    const Matrix<N, 1> z_ref = llt.matrixU().solve(b);
    CHECK((z - z_ref).cwiseAbs().maxCoeff() < 1e-12 * std::max(1.0, z_ref.cwiseAbs().maxCoeff()));

    // Both triangular solves together solve A x = b.
    Matrix<N, 1> x = b;
    mbrt::solve_lower<N>(L, x);
    mbrt::solve_lower_transposed<N>(L, x);
    const Matrix<N, 1> x_ref = llt.solve(b);
    CHECK((x - x_ref).cwiseAbs().maxCoeff() < 1e-12 * std::max(1.0, x_ref.cwiseAbs().maxCoeff()));
    CHECK((A * x - b).cwiseAbs().maxCoeff() < 1e-12 * scale * std::max(1.0, x.cwiseAbs().maxCoeff()));

    // Three right-hand sides at once: A^-1 B.
    const Matrix<N, 3> B = rnd.matrix<N, 3>();
    Matrix<N, 3> X3 = B;
    mbrt::solve_factored<N, 3>(L, X3);
    const Matrix<N, 3> X3_ref = llt.solve(B);
    CHECK((X3 - X3_ref).cwiseAbs().maxCoeff() < 1e-12 * std::max(1.0, X3_ref.cwiseAbs().maxCoeff()));

    // X L^-T for a block with 2 and with N rows: (L^-1 X^T)^T.
    const Matrix<2, N> X2 = rnd.matrix<2, N>();
    Matrix<2, N> Y2 = X2;
    mbrt::solve_right_lower_transposed<2, N>(L, Y2);
    const Matrix<2, N> Y2_ref = Matrix<N, 2>(llt.matrixL().solve(X2.transpose())).transpose();
    CHECK((Y2 - Y2_ref).cwiseAbs().maxCoeff() < 1e-12 * std::max(1.0, Y2_ref.cwiseAbs().maxCoeff()));
    CHECK((Y2 * L.transpose() - X2).cwiseAbs().maxCoeff() < 1e-12 * std::sqrt(scale));

    const Matrix<N, N> XN = rnd.matrix<N, N>();
    Matrix<N, N> YN = XN;
    mbrt::solve_right_lower_transposed<N, N>(L, YN);
    CHECK((YN * L.transpose() - XN).cwiseAbs().maxCoeff() < 1e-12 * std::sqrt(scale));
  }
}

TEST_CASE("cholesky_in_place gives L L^T = A and the solves match Eigen's LLT (N = 1..6)") {
  Random rnd(401);
  check_factor_and_solves<1>(rnd);
  check_factor_and_solves<2>(rnd);
  check_factor_and_solves<3>(rnd);
  check_factor_and_solves<4>(rnd);
  check_factor_and_solves<5>(rnd);
  check_factor_and_solves<6>(rnd);
}

TEST_CASE("cholesky_in_place of a hand example") {
  Matrix<3, 3> A;
  A << 4, 12, -16,
       12, 37, -43,
       -16, -43, 98;
  Matrix<3, 3> L_expected;
  L_expected << 2, 0, 0,
                6, 1, 0,
                -8, 5, 3;
  REQUIRE(mbrt::cholesky_in_place<3>(A));
  CHECK((lower_of<3>(A) - L_expected).cwiseAbs().maxCoeff() < 1e-14);
}

template <int N>
void check_not_positive(Random& rnd) {
  INFO("N = " << N);
  // Zero, negative definite, and indefinite with the negative eigenvalue anywhere.
  std::vector<Matrix<N, N>> cases = {Matrix<N, N>::Zero(), -random_spd<N>(rnd, 1.0)};
  for (int k = 0; k < N; ++k) {
    Matrix<N, 1> lambda = Matrix<N, 1>::Ones();
    lambda[k] = -0.5;
    const Matrix<N, N> Q = rnd.orthogonal<N>();
    cases.push_back(Q * lambda.asDiagonal() * Q.transpose());
    // Diagonal matrix with one non-positive pivot at position k.
    Matrix<N, N> D = Matrix<N, N>::Identity();
    D(k, k) = k % 2 == 0 ? 0.0 : -1.0;
    cases.push_back(D);
  }
  for (std::size_t i = 0; i < cases.size(); ++i) {
    INFO("case " << i);
    Matrix<N, N> F = cases[i];
    CHECK_FALSE(mbrt::cholesky_in_place<N>(F));
    CHECK(F.allFinite());
  }
}

TEST_CASE("cholesky_in_place returns false with a finite factor when A is not positive definite") {
  Random rnd(402);
  check_not_positive<1>(rnd);
  check_not_positive<2>(rnd);
  check_not_positive<3>(rnd);
  check_not_positive<4>(rnd);
  check_not_positive<5>(rnd);
  check_not_positive<6>(rnd);
}

}  // namespace
