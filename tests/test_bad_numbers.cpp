// Bad numbers never enter the state: a diverging step returns a status and
// leaves the last good state in place; a NaN put into the state is refused.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "a01_pendulum.hpp"
#include "unstable_spring.hpp"

namespace spring = mbrt::models::unstable_spring;
namespace pendulum = mbrt::models::a01_pendulum;

TEST_CASE("a diverging step reports non_finite and keeps the last finite state") {
  spring::State s = spring::initial_state();
  mbrt::StepStatus status = mbrt::StepStatus::ok;
  long steps = 0;
  spring::State last_ok = s;
  for (; steps < 100000 && status == mbrt::StepStatus::ok; ++steps) {
    last_ok = s;
    status = spring::step(s);
  }
  REQUIRE(status == mbrt::StepStatus::non_finite);
  MESSAGE("diverged after " << steps << " steps");
  CHECK(s.particle[0].r.allFinite());
  CHECK(s.particle[0].v.allFinite());
  CHECK(s.t == last_ok.t);
  CHECK(s.particle[0].r == last_ok.particle[0].r);
  // Further calls fail the same way and change nothing.
  CHECK(spring::step(s) == mbrt::StepStatus::non_finite);
  CHECK(s.particle[0].r == last_ok.particle[0].r);
}

TEST_CASE("a NaN written into the state is refused without spreading") {
  pendulum::State s = pendulum::initial_state();
  for (int i = 0; i < 10; ++i) pendulum::step(s);
  s.particle[0].v.x() = std::numeric_limits<double>::quiet_NaN();
  const double t = s.t;
  CHECK(pendulum::step(s) == mbrt::StepStatus::non_finite);
  CHECK(s.t == t);  // nothing advanced
  s.particle[0].v.x() = 0.0;  // the caller repairs its input; stepping resumes
  CHECK(pendulum::step(s) == mbrt::StepStatus::ok);
}

TEST_CASE("an absurd velocity written into the state gives a status, not an overflowed state") {
  pendulum::State s = pendulum::initial_state();
  for (int i = 0; i < 10; ++i) pendulum::step(s);
  s.particle[0].v.y() = 1e300;  // its centripetal force overflows a double
  const pendulum::State before = s;
  CHECK(pendulum::step(s) == mbrt::StepStatus::non_finite);
  CHECK(s.t == before.t);
  CHECK(s.particle[0].r == before.particle[0].r);
  CHECK(s.particle[0].v == before.particle[0].v);
}
