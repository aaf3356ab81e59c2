// Observed order of accuracy of staggered-pcst: errors at h, h/2, h/4
// against a run 64x finer, for a constrained spinning body (heavy top) and
// a free asymmetric body. The method is second order.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "free_body_1.hpp"
#include "free_body_2.hpp"
#include "free_body_4.hpp"
#include "free_body_ref.hpp"
#include "heavy_top_1.hpp"
#include "heavy_top_2.hpp"
#include "heavy_top_4.hpp"
#include "heavy_top_ref.hpp"

namespace {

struct Final {
  mbrt::Vec3 r;
  mbrt::Mat3 R;
  mbrt::Vec3 w;
};

// Runs a generated model (by namespace) to t_end.
#define RUN_TO(model, t_end)                                                        \
  [&] {                                                                             \
    namespace m = mbrt::models::model;                                              \
    m::State s = m::initial_state();                                                \
    const long n = std::lround((t_end) / m::kStep);                                 \
    for (long i = 0; i < n; ++i) REQUIRE(m::step(s) == mbrt::StepStatus::ok);       \
    return Final{s.rigid[0].r, mbrt::rotation_matrix(s.rigid[0].p), s.rigid[0].w};  \
  }()

double error(const Final& a, const Final& ref) {
  return (a.r - ref.r).norm() + (a.R - ref.R).norm() + (a.w - ref.w).norm() / std::max(1.0, ref.w.norm());
}

void check_second_order(const char* what, const Final& h1, const Final& h2, const Final& h4, const Final& ref) {
  const double e1 = error(h1, ref), e2 = error(h2, ref), e4 = error(h4, ref);
  const double p12 = std::log2(e1 / e2), p24 = std::log2(e2 / e4);
  MESSAGE(what << ": errors " << e1 << ", " << e2 << ", " << e4 << "; observed orders " << p12 << ", " << p24);
  CHECK(p12 > 1.8);
  CHECK(p12 < 2.3);
  CHECK(p24 > 1.8);
  CHECK(p24 < 2.3);
}

}  // namespace

TEST_CASE("heavy top converges with order 2") {
  const double t_end = 0.5;
  check_second_order("heavy top, h = 4e-4, 2e-4, 1e-4", RUN_TO(heavy_top_1, t_end), RUN_TO(heavy_top_2, t_end),
                     RUN_TO(heavy_top_4, t_end), RUN_TO(heavy_top_ref, t_end));
}

TEST_CASE("free asymmetric body converges with order 2") {
  const double t_end = 4.0;
  check_second_order("free body, h = 8e-3, 4e-3, 2e-3", RUN_TO(free_body_1, t_end), RUN_TO(free_body_2, t_end),
                     RUN_TO(free_body_4, t_end), RUN_TO(free_body_ref, t_end));
}
