// IFToMM / lim.ii.udc.es benchmark A01 (simple pendulum) over 2000 s.
//
// Reference: the minimal-coordinate equation phi'' = -g cos(phi) (phi: bar
// angle from +x, phi(0) = pi, g = 9.81, L = 1) integrated by classical RK4 at
// a step half the model's. A few values of the published table
// (A01_solution_data.txt of the benchmark, 6 significant digits) check that
// reference itself.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "a01_pendulum.hpp"
#include "a01_revolute_rk4_128.hpp"
#include "a01_revolute_rk4_256.hpp"
#include "reference_solutions.hpp"

namespace model = mbrt::models::a01_pendulum;

namespace {

// Largest distance of the bob from the reference at every 0.5 s up to 2000 s,
// for the tree form of A01 (tests/models/a01_revolute.yaml).
template <class State, class Step>
double a01_tree_error(State s, Step step, double h, const std::vector<mbrt::Vec3>& ref, int bob) {
  const long per_sample = std::lround(0.5 / h);
  double worst = 0.0;
  for (size_t k = 1; k < ref.size(); ++k) {
    for (long i = 0; i < per_sample; ++i) REQUIRE(step(s) == mbrt::StepStatus::ok);
    const mbrt::Vec3& r = s.rigid[static_cast<size_t>(bob)].r;
    worst = std::max(worst, std::hypot(r.x() - ref[k].x(), r.y() - ref[k].y()));
  }
  return worst;
}

}  // namespace


TEST_CASE("A01 pendulum stays within 1e-3 m of the reference at every 0.5 s output up to 2000 s") {
  const double t_end = 2000.0, dt = 0.5;
  const std::vector<mbrt::Vec3> ref = reference::a01_bob_positions(t_end, dt, model::kStep / 2.0);

  // Published benchmark values (t, x, y): the reference must reproduce them.
  const struct { double t, x, y; } published[] = {
      {0.5, -0.391049, -0.920370}, {10.0, -0.275087, -0.961419}, {100.0, -0.181513, -0.983388},
      {1000.0, 0.683230, -0.730203}, {2000.0, 0.814603, -0.580019}};
  for (const auto& p : published) {
    const mbrt::Vec3& r = ref[static_cast<size_t>(std::lround(p.t / dt))];
    CHECK(std::abs(r.x() - p.x) < 2e-6);
    CHECK(std::abs(r.y() - p.y) < 2e-6);
  }

  model::State s = model::initial_state();
  const long per_sample = std::lround(dt / model::kStep);
  double worst = 0.0, worst_violation = 0.0, worst_tension = 0.0;
  for (size_t k = 1; k < ref.size(); ++k) {
    for (long i = 0; i < per_sample; ++i) REQUIRE(model::step(s) == mbrt::StepStatus::ok);
    const mbrt::Vec3& r = s.particle[0].r;
    worst = std::max(worst, std::max(std::abs(r.x() - ref[k].x()), std::abs(r.y() - ref[k].y())));
    worst_violation = std::max(worst_violation, model::constraint_violation(s).position);
    // The multiplier of the distance row is the bar tension; from energy
    // conservation (v^2 = -2 g y) and the radial balance, T = -3 m g y.
    worst_tension = std::max(worst_tension, std::abs(s.lambda[0] - (-3.0 * 9.81 * r.y())));
  }
  MESSAGE("h = " << model::kStep << ": max position error " << worst << " m, max |phi| " << worst_violation
                 << ", max tension error " << worst_tension << " N (of up to 29.4 N)");
  CHECK(worst < 1e-3);
  CHECK(worst_violation < 1e-10);
  CHECK(worst_tension < 1e-2);
  CHECK(std::abs(model::energy(s).total()) < 1e-5);  // E = 0 with y = 0 at the pivot
}

// rk4-tree at the precision the benchmark calls high, 1e-3 m over 2000 s, at
// steps 32 and 16 times the one above (measured: 4.3e-4 m at 1/128 s, 1.3e-5
// m at 1/256 s). Fourth order: the phase error per swing falls 16 times per
// halving of h. Over 2000 s another term leads: the method loses energy at a
// rate O(h^5), and the period of a swing this wide depends on its energy, so
// the phase drifts as h^5 t^2; the observed ratio is 33. A second-order
// scheme at these steps would be off by metres.
TEST_CASE("rk4-tree holds A01 within 1e-3 m over 2000 s at h = 1/128 s, with fourth-order convergence") {
  namespace coarse = mbrt::models::a01_revolute_rk4_128;
  namespace fine = mbrt::models::a01_revolute_rk4_256;
  const std::vector<mbrt::Vec3> ref = reference::a01_bob_positions(2000.0, 0.5, 1e-4);
  const double e128 = a01_tree_error(coarse::initial_state(), [](coarse::State& s) { return coarse::step(s); },
                                     coarse::kStep, ref, coarse::rigid::bob);
  const double e256 = a01_tree_error(fine::initial_state(), [](fine::State& s) { return fine::step(s); },
                                     fine::kStep, ref, fine::rigid::bob);
  MESSAGE("largest bob error over 2000 s: " << e128 << " m at h = 1/128 s, " << e256 << " m at 1/256 s");
  CHECK(e128 < 1e-3);
  CHECK(e128 / e256 > 12.0);
  CHECK(e128 / e256 < 40.0);
}
