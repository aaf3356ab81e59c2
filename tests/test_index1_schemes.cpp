// The index-1 schemes (baumgarte, blajer) on the reference problems: A01
// against the minimal-coordinate solution, the closed four-bar's
// violations, and second-order convergence on the heavy top.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include <vector>

#include "convergence.hpp"
#include "reference_solutions.hpp"

#include "a01_baumgarte.hpp"
#include "a01_blajer.hpp"
#include "four_bar_baumgarte.hpp"
#include "four_bar_blajer.hpp"
#include "heavy_top_baumgarte_1.hpp"
#include "heavy_top_baumgarte_2.hpp"
#include "heavy_top_baumgarte_4.hpp"
#include "heavy_top_baumgarte_ref.hpp"
#include "heavy_top_blajer_1.hpp"
#include "heavy_top_blajer_2.hpp"
#include "heavy_top_blajer_4.hpp"
#include "heavy_top_blajer_ref.hpp"

namespace {

#define A01_ERROR(model, t_end)                                                                        \
  [] {                                                                                                 \
    namespace m = mbrt::models::model;                                                                 \
    const std::vector<mbrt::Vec3> ref = reference::a01_bob_positions((t_end), 0.5, m::kStep / 2);      \
    m::State s = m::initial_state();                                                                   \
    double worst = 0.0;                                                                                \
    for (size_t k = 1; k < ref.size(); ++k) {                                                          \
      while (s.t < 0.5 * static_cast<double>(k) - 0.5 * m::kStep) REQUIRE(m::step(s) == mbrt::StepStatus::ok); \
      worst = std::max(worst, (s.particle[0].r - ref[k]).cwiseAbs().maxCoeff());                       \
    }                                                                                                  \
    return worst;                                                                                      \
  }()

#define FOUR_BAR_VIOLATION(model, steps)                                  \
  [] {                                                                    \
    namespace m = mbrt::models::model;                                    \
    m::State s = m::initial_state();                                      \
    mbrt::ConstraintViolation worst{0.0, 0.0, 0.0};                            \
    for (long i = 1; i <= (steps); ++i) {                                 \
      REQUIRE(m::step(s) == mbrt::StepStatus::ok);                        \
      if (i % 100 == 0) {                                                 \
        const mbrt::ConstraintViolation v = m::constraint_violation(s);   \
        worst.position = std::max(worst.position, v.position);            \
        worst.velocity = std::max(worst.velocity, v.velocity);            \
      }                                                                   \
    }                                                                     \
    return worst;                                                         \
  }()

}  // namespace

TEST_CASE("A01 over 100 s at h = 2.5e-4: baumgarte within 2e-4 m, blajer within 1e-5 m") {
  const double baumgarte = A01_ERROR(a01_baumgarte, 100.0);
  const double blajer = A01_ERROR(a01_blajer, 100.0);
  MESSAGE("max position error over 100 s: baumgarte " << baumgarte << ", blajer " << blajer);
  CHECK(baumgarte < 2e-4);
  CHECK(blajer < 1e-5);
}

TEST_CASE("closed four-bar over 2e5 steps: violations stay bounded in both index-1 schemes") {
  const mbrt::ConstraintViolation baumgarte = FOUR_BAR_VIOLATION(four_bar_baumgarte, 200000);
  const mbrt::ConstraintViolation blajer = FOUR_BAR_VIOLATION(four_bar_blajer, 200000);
  MESSAGE("baumgarte |phi| " << baumgarte.position << " |phi'| " << baumgarte.velocity << "; blajer |phi| "
                             << blajer.position << " |phi'| " << blajer.velocity);
  CHECK(baumgarte.position < 1e-5);
  CHECK(baumgarte.velocity < 1e-3);
  CHECK(blajer.position < 1e-10);  // corrected after every step
  CHECK(blajer.velocity < 1e-6);   // bounded by the regularization of the 3 redundant rows
}

TEST_CASE("baumgarte and blajer converge with order 2 on the heavy top") {
  const double t_end = 0.5;
  // Baumgarte's default gains scale as 1/h, so the stabilized equations
  // themselves change with h: the order reaches 2 only as h shrinks
  // (measured 1.81, then 1.98).
  convergence::check_second_order("baumgarte", MBRT_RUN_TO(heavy_top_baumgarte_1, t_end),
                                  MBRT_RUN_TO(heavy_top_baumgarte_2, t_end), MBRT_RUN_TO(heavy_top_baumgarte_4, t_end),
                                  MBRT_RUN_TO(heavy_top_baumgarte_ref, t_end), 1.7);
  convergence::check_second_order("blajer", MBRT_RUN_TO(heavy_top_blajer_1, t_end),
                                  MBRT_RUN_TO(heavy_top_blajer_2, t_end), MBRT_RUN_TO(heavy_top_blajer_4, t_end),
                                  MBRT_RUN_TO(heavy_top_blajer_ref, t_end));
}
