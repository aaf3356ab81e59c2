// Observed order of accuracy of staggered-pcst: errors at h, h/2, h/4
// against a run 64x finer, for a constrained spinning body (heavy top) and
// a free asymmetric body. The method is second order.
#include "convergence.hpp"

#include "free_body_1.hpp"
#include "free_body_2.hpp"
#include "free_body_4.hpp"
#include "free_body_ref.hpp"
#include "heavy_top_1.hpp"
#include "heavy_top_2.hpp"
#include "heavy_top_4.hpp"
#include "heavy_top_ref.hpp"

TEST_CASE("heavy top converges with order 2") {
  const double t_end = 0.5;
  convergence::check_second_order("heavy top, h = 4e-4, 2e-4, 1e-4", MBRT_RUN_TO(heavy_top_1, t_end),
                                  MBRT_RUN_TO(heavy_top_2, t_end), MBRT_RUN_TO(heavy_top_4, t_end),
                                  MBRT_RUN_TO(heavy_top_ref, t_end));
}

TEST_CASE("free asymmetric body converges with order 2") {
  const double t_end = 4.0;
  convergence::check_second_order("free body, h = 8e-3, 4e-3, 2e-3", MBRT_RUN_TO(free_body_1, t_end),
                                  MBRT_RUN_TO(free_body_2, t_end), MBRT_RUN_TO(free_body_4, t_end),
                                  MBRT_RUN_TO(free_body_ref, t_end));
}
