// Closed four-bar (planar loop with redundant rows) over a long run: the
// constraint violation stays bounded and does not grow; ideal joints do no
// work, so energy is held.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "four_bar.hpp"

namespace model = mbrt::models::four_bar;

TEST_CASE("closed four-bar: constraint violation stays bounded over 2e5 steps") {
  model::State s = model::initial_state();
  const double E0 = model::energy(s).total();
  const long steps = 200000;
  double first_half = 0, second_half = 0, max_velocity = 0, max_dE = 0;
  for (long i = 1; i <= steps; ++i) {
    REQUIRE(model::step(s) == mbrt::StepStatus::ok);
    if (i % 100 == 0) {
      const mbrt::ConstraintViolation v = model::constraint_violation(s);
      (i <= steps / 2 ? first_half : second_half) = std::max(i <= steps / 2 ? first_half : second_half, v.position);
      max_velocity = std::max(max_velocity, v.velocity);
      max_dE = std::max(max_dE, std::abs(model::energy(s).total() - E0));
    }
  }
  MESSAGE("t = " << s.t << " s: max |phi| " << first_half << " (first half), " << second_half
                 << " (second half); max |phi_dot| " << max_velocity << "; max |dE| " << max_dE << " J of " << E0);
  // Position residuals are the O(h^3) per-step remainder the stabilization
  // removes; velocity residuals come from the penalty regularization.
  CHECK(first_half < 1e-7);
  CHECK(second_half < 1e-7);
  CHECK(second_half < 2 * first_half);  // no growth
  CHECK(max_velocity < 1e-6);
  CHECK(max_dE < 1e-3 * std::abs(E0));
}

TEST_CASE("closed four-bar actually moves") {
  model::State s = model::initial_state();
  const mbrt::Vec3 start = s.rigid[1].r;
  for (int i = 0; i < 1000; ++i) model::step(s);
  CHECK((s.rigid[1].r - start).norm() > 0.5);  // the coupler moved about 1 m/s
}
