// staggered-nps (docs/staggered-nps.md): trees against independent
// references and conservation laws, every tree joint type against
// staggered-pcst, a closed loop through its cut rows, and second-order
// convergence on the heavy top.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include <vector>

#include "convergence.hpp"
#include "reference_solutions.hpp"

#include "branched_tree_nps.hpp"
#include "branched_tree_pcst.hpp"
#include "chain_10_nps.hpp"
#include "four_bar_nps.hpp"
#include "heavy_top_nps.hpp"
#include "heavy_top_nps_1.hpp"
#include "heavy_top_nps_2.hpp"
#include "heavy_top_nps_4.hpp"
#include "heavy_top_nps_ref.hpp"

TEST_CASE("10-link chain: tip against Lagrange's equations in the link angles; B u = 0 exactly on the tree") {
  namespace m = mbrt::models::chain_10_nps;
  const double dt = 0.1, t_end = 2.0;
  const std::vector<mbrt::Vec3> ref = reference::chain_tip_positions(10, t_end, dt, 1e-5);
  m::State s = m::initial_state();
  double worst = 0.0, velocity = 0.0;
  for (size_t k = 1; k < ref.size(); ++k) {
    while (s.t < dt * static_cast<double>(k) - 0.5 * m::kStep) {
      REQUIRE(m::step(s) == mbrt::StepStatus::ok);
      velocity = std::max(velocity, m::constraint_violation(s).velocity);
    }
    const mbrt::Vec3 tip = s.rigid[9].r + mbrt::rotation_matrix(s.rigid[9].p) * mbrt::Vec3(0.5, 0.0, 0.0);
    worst = std::max(worst, (tip - ref[k]).norm());
  }
  MESSAGE("tip error over 2 s at h = 1e-3: " << worst << " m; max |B u| " << velocity << " m/s");
  CHECK(worst < 2e-4);  // measured 7.5e-5 m
  CHECK(velocity < 1e-12);
}

TEST_CASE("heavy top, h = 1e-4: height of the centre of mass against the integrable Lagrange top") {
  namespace m = mbrt::models::heavy_top_nps;
  m::State s = m::initial_state();
  double worst = 0.0, velocity = 0.0;
  for (const reference::TimedValue& v : reference::kHeavyTopHeight) {
    while (s.t < v.t - 0.5 * m::kStep) {
      REQUIRE(m::step(s) == mbrt::StepStatus::ok);
      velocity = std::max(velocity, m::constraint_violation(s).velocity);
    }
    worst = std::max(worst, std::abs(s.rigid[0].r.z() - v.value));
  }
  MESSAGE("max height error over 2 s: " << worst << " m; max |B u| " << velocity << " m/s");
  CHECK(worst < 1e-5);  // measured 2.3e-6 m
  CHECK(velocity < 1e-12);
}

TEST_CASE("staggered-nps converges with order 2 on the heavy top") {
  const double t_end = 0.5;
  convergence::check_second_order("staggered-nps", MBRT_RUN_TO(heavy_top_nps_1, t_end),
                                  MBRT_RUN_TO(heavy_top_nps_2, t_end), MBRT_RUN_TO(heavy_top_nps_4, t_end),
                                  MBRT_RUN_TO(heavy_top_nps_ref, t_end));
}

TEST_CASE("branched tree of every tree joint type: energy kept, same motion as staggered-pcst") {
  namespace nps = mbrt::models::branched_tree_nps;
  namespace pcst = mbrt::models::branched_tree_pcst;
  nps::State a = nps::initial_state();
  pcst::State b = pcst::initial_state();
  const double e0 = nps::energy(a).total();
  double drift = 0.0, apart = 0.0, velocity = 0.0, travel = 0.0;
  for (int i = 1; i <= 10000; ++i) {  // 2 s
    REQUIRE(nps::step(a) == mbrt::StepStatus::ok);
    REQUIRE(pcst::step(b) == mbrt::StepStatus::ok);
    if (i % 50 != 0) continue;
    drift = std::max(drift, std::abs(nps::energy(a).total() - e0));
    velocity = std::max(velocity, nps::constraint_violation(a).velocity);
    for (int k = 0; k < nps::kRigidBodies; ++k) {
      apart = std::max(apart, (a.rigid[k].r - b.rigid[k].r).norm());
      travel = std::max(travel, (a.rigid[k].r - nps::initial_state().rigid[k].r).norm());
    }
  }
  MESSAGE("|E - E0| " << drift << " J; max distance from staggered-pcst's bodies " << apart << " m (bodies travel "
                      << travel << " m); max |B u| " << velocity << " m/s");
  CHECK(travel > 0.1);  // it does move
  CHECK(drift < 1e-6);
  CHECK(apart < 1e-6);
  CHECK(velocity < 1e-10);
}

TEST_CASE("closed four-bar through one cut joint: violations bounded, energy kept over 2e5 steps") {
  namespace m = mbrt::models::four_bar_nps;
  m::State s = m::initial_state();
  const double e0 = m::energy(s).total();
  mbrt::ConstraintViolation worst{0.0, 0.0, 0.0};
  double drift = 0.0;
  for (long i = 1; i <= 200000; ++i) {
    REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    if (i % 100 != 0) continue;
    const mbrt::ConstraintViolation v = m::constraint_violation(s);
    worst.position = std::max(worst.position, v.position);
    worst.velocity = std::max(worst.velocity, v.velocity);
    drift = std::max(drift, std::abs(m::energy(s).total() - e0));
  }
  MESSAGE("|phi| " << worst.position << ", |phi'| " << worst.velocity << ", |E - E0| " << drift << " J of " << e0);
  CHECK(worst.position < 1e-7);
  CHECK(worst.velocity < 1e-6);
  CHECK(drift < 2e-3);  // 1.2e-3 J, the level staggered-pcst keeps at h = 1e-3 too
}
