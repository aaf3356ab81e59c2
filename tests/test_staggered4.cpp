// staggered4 (docs/schemes.md, "staggered4"), staggered-pcst composed by
// Yoshida's triple jump, against independent references: its order on the
// heavy top (the closed-form Lagrange top), on A01 (the minimal-coordinate
// equation) and on the 7-link arm in absolute coordinates (Simbody); the
// constraints and the Euler parameters on the four-bar, whose loop has
// redundant rows; and its energy, which a symmetric method keeps bounded
// where rk4-projected's drifts.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "a01_s4_128.hpp"
#include "a01_s4_256.hpp"
#include "arm_7_s4.hpp"
#include "arm_7_s4_2ms.hpp"
#include "four_bar_s4.hpp"
#include "heavy_top_s4_1.hpp"
#include "heavy_top_s4_2.hpp"
#include "heavy_top_s4_4.hpp"
#include "reference_errors.hpp"

TEST_CASE("staggered4 is fourth order on the heavy top") {
  const double e1 = HEAVY_TOP_HEIGHT_ERROR(heavy_top_s4_1);
  const double e2 = HEAVY_TOP_HEIGHT_ERROR(heavy_top_s4_2);
  const double e4 = HEAVY_TOP_HEIGHT_ERROR(heavy_top_s4_4);
  MESSAGE("heavy top height error up to 1 s: " << e1 << ", " << e2 << ", " << e4 << " m at h = 1e-3, 5e-4, 2.5e-4");
  CHECK(e1 < 1e-5);
  CHECK(e1 / e2 > 12.0);
  CHECK(e2 / e4 > 12.0);
  CHECK(e1 / e2 < 20.0);
  CHECK(e2 / e4 < 20.0);
}

// rk4-projected's error falls 32 times per halving here (its energy loss of
// order h^5 moves the phase as h^5 t^2); a symmetric step's phase error grows
// as h^4 t, so staggered4's falls 16 times.
TEST_CASE("staggered4 on A01 over 2000 s: within 1e-3 m at h = 1/256 s, fourth order") {
  const std::vector<mbrt::Vec3> ref = reference::a01_bob_positions(2000.0, 0.5, 1e-4);
  const double e128 = A01_ERROR(a01_s4_128, ref);
  const double e256 = A01_ERROR(a01_s4_256, ref);
  MESSAGE("A01 largest error over 2000 s: " << e128 << " m at h = 1/128 s, " << e256 << " m at 1/256 s");
  CHECK(e256 < 1e-3);
  CHECK(e128 / e256 > 12.0);
  CHECK(e128 / e256 < 20.0);
}

TEST_CASE("staggered4 on the 7-link arm in absolute coordinates follows Simbody's reference to fourth order") {
  const double e2 = ARM_TIP_ERROR(arm_7_s4_2ms);
  const double e1 = ARM_TIP_ERROR(arm_7_s4);
  MESSAGE("arm tip error after 0.5 s: " << e2 << " m at h = 2e-3, " << e1 << " m at 1e-3");
  CHECK(e1 < 1e-8);
  CHECK(e2 / e1 > 12.0);
  CHECK(e2 / e1 < 20.0);
}

// Three of the loop's 20 rows are redundant: the regularized factor, the
// position stage's Newton steps and the velocity projection take them as
// they are.
TEST_CASE("staggered4 holds the four-bar's constraints to round-off and |p| = 1") {
  namespace m = mbrt::models::four_bar_s4;
  m::State s = m::initial_state();
  double worst_position = 0.0, worst_velocity = 0.0;
  for (int k = 1; k <= 20000; ++k) {  // 20 s at 1e-3
    REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    const mbrt::ConstraintViolation v = m::constraint_violation(s);
    worst_position = std::max(worst_position, v.position);
    worst_velocity = std::max(worst_velocity, v.velocity);
  }
  MESSAGE("four-bar over 20 s: |phi| " << worst_position << ", |phi'| " << worst_velocity << ", | |p| - 1 | "
                                       << m::quaternion_norm_error(s));
  CHECK(worst_position < 1e-12);
  CHECK(worst_velocity < 1e-12);
  CHECK(m::quaternion_norm_error(s) < 1e-14);
}

// Largest energy error in each tenth of a run of `tenths` x `steps` steps.
#define ENERGY_ERROR_BY_TENTH(model, steps)                                               \
  [] {                                                                                    \
    namespace m = mbrt::models::model;                                                    \
    m::State s = m::initial_state();                                                      \
    const double e0 = m::energy(s).total();                                               \
    std::vector<double> worst(10, 0.0);                                                   \
    for (double& w : worst) {                                                             \
      for (long k = 0; k < (steps); ++k) {                                                \
        REQUIRE(m::step(s) == mbrt::StepStatus::ok);                                      \
        w = std::max(w, std::abs(m::energy(s).total() - e0));                             \
      }                                                                                   \
    }                                                                                     \
    return worst;                                                                         \
  }()

// A symmetric step's energy error oscillates: over the last tenth of a long
// run it is as large as over the first, where a drift would have grown it
// ten-fold. The heavy top spins at 150 rad/s; with two Newton steps in the
// position stage instead of six its energy drifted by 1.3e-4 J/s at 1e-3,
// and rk4-projected's gains 1.2e-3 J in its first second at 1e-3. On the
// four-bar (measured: 5.2e-8 J over the first 10 s, 8.1e-8 J over the last)
// a slow drift remains, of the order of S's regularization along its
// redundant rows.
TEST_CASE("staggered4 keeps the heavy top's energy bounded, without drift, and the four-bar's within 2e-7 J") {
  const std::vector<double> top = ENERGY_ERROR_BY_TENTH(heavy_top_s4_1, 10000);  // 100 s at 1e-3
  const std::vector<double> loop = ENERGY_ERROR_BY_TENTH(four_bar_s4, 10000);     // 100 s at 1e-3
  MESSAGE("heavy top energy error, first and last 10 s of 100 s: " << top.front() << ", " << top.back() << " J");
  MESSAGE("four-bar energy error, first and last 10 s of 100 s: " << loop.front() << ", " << loop.back() << " J");
  CHECK(top.back() < 2.0 * top.front());
  CHECK(top.back() < 1e-3);
  CHECK(loop.back() < 2e-7);
}
