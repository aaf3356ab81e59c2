// mbrt::flag: 1.0 and +0.0 exactly, the values static_cast<double>(bool) gives.
#include <doctest/doctest.h>

#include <cmath>

#include <mbrt/flag.hpp>

TEST_CASE("flag gives 1.0 where the condition holds and +0.0 where not") {
  volatile double x = 0.3;  // conditions the compiler cannot fold
  CHECK(mbrt::flag(x < 0.5) == 1.0);
  CHECK(mbrt::flag(x > 0.5) == 0.0);
  CHECK_FALSE(std::signbit(mbrt::flag(x > 0.5)));
  CHECK(mbrt::flag(std::isnan(x)) == 0.0);
  CHECK(mbrt::flag(x < 0.5) * 7.0 == 7.0);
}
