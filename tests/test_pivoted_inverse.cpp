// mbrt::invert_with_pivoting against Eigen's LU with full pivoting, on
// random and on hand-made matrices whose leading entry is zero or tiny (a
// Gauss-Jordan sweep without row exchanges fails or loses the digits there).
#include <doctest/doctest.h>

#include <Eigen/Dense>

#include <mbrt/pivoted_inverse.hpp>

namespace {

template <int N>
void check_random(int draws) {
  std::srand(7);
  for (int d = 0; d < draws; ++d) {
    const Eigen::Matrix<double, N, N> a = Eigen::Matrix<double, N, N>::Random() + 0.1 * Eigen::Matrix<double, N, N>::Identity();
    Eigen::Matrix<double, N, N> x = a;
    mbrt::invert_with_pivoting(x);
    const Eigen::Matrix<double, N, N> reference = a.fullPivLu().inverse();
    const double condition = a.norm() * reference.norm();
    CAPTURE(N);
    CHECK((x - reference).norm() <= 1e-13 * condition * reference.norm());
    CHECK((a * x - Eigen::Matrix<double, N, N>::Identity()).norm() <= 1e-13 * condition);
  }
}

}  // namespace

TEST_CASE("invert_with_pivoting matches Eigen's full-pivoting LU (N = 1..6)") {
  check_random<1>(50);
  check_random<2>(200);
  check_random<3>(200);
  check_random<4>(200);
  check_random<5>(200);
  check_random<6>(200);
}

TEST_CASE("invert_with_pivoting exchanges rows where the pivot is zero or tiny") {
  Eigen::Matrix2d swap;
  swap << 0.0, 2.0, 4.0, 0.0;
  Eigen::Matrix2d x = swap;
  mbrt::invert_with_pivoting(x);
  Eigen::Matrix2d expected;
  expected << 0.0, 0.25, 0.5, 0.0;
  CHECK((x - expected).norm() == 0.0);

  // Without the exchange the 1e-20 pivot would wipe out the 1 in the sum 1 - 1e20.
  Eigen::Matrix3d tiny;
  tiny << 1e-20, 1.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 3.0;
  Eigen::Matrix3d y = tiny;
  mbrt::invert_with_pivoting(y);
  CHECK((tiny * y - Eigen::Matrix3d::Identity()).norm() < 1e-15);
}

TEST_CASE("a singular matrix gives non-finite entries") {
  Eigen::Matrix2d singular;
  singular << 1.0, 2.0, 2.0, 4.0;
  mbrt::invert_with_pivoting(singular);
  CHECK(!singular.allFinite());
}
