// mbrt::sin_cos against the C library's sin and cos: within 1 ulp of 1 over
// the angles a joint reaches, and exact where the reduction leaves r = 0.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <mbrt/sin_cos.hpp>

TEST_CASE("sin_cos agrees with std::sin and std::cos to 1 ulp of 1 up to 1e5 rad") {
  std::mt19937_64 random(7);
  double worst = 0.0;
  for (const double range : {1.0, 10.0, 1e3, 1e5}) {
    std::uniform_real_distribution<double> angle(-range, range);
    for (int i = 0; i < 200000; ++i) {
      const double x = angle(random);
      const mbrt::SinCos y = mbrt::sin_cos(x);
      worst = std::max({worst, std::abs(y.s - std::sin(x)), std::abs(y.c - std::cos(x))});
    }
  }
  MESSAGE("largest difference " << worst);
  CHECK(worst <= 2.3e-16);
}

TEST_CASE("sin_cos turns through the quadrants") {
  const mbrt::SinCos zero = mbrt::sin_cos(0.0);
  CHECK(zero.c == 1.0);
  CHECK(zero.s == 0.0);
  for (int k = -8; k <= 8; ++k) {
    const double x = 0.3 + k * M_PI / 2;
    const mbrt::SinCos y = mbrt::sin_cos(x);
    CHECK(std::abs(y.s - std::sin(x)) < 1e-15);
    CHECK(std::abs(y.c - std::cos(x)) < 1e-15);
  }
}
